#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "pipescope/camera/camera.h"
#include "pipescope/estimation/wall_distance_observability.h"
#include "pipescope/geometry/camera_mount.h"
#include "pipescope/io/dataset.h"
#include "pipescope/io/trajectory.h"

namespace pipescope {

// What a wall-camera run knows of the camera's distance to the wall, which sets its scale
// (issue 22): whether the method measures it along the run or holds the start's, whether this
// view could measure it at all, and what an error in it costs. For run.json and the summary.
struct WallDistanceStatement {
  double start_m = 0.0;          // the start's distance to the wall the run used
  std::string start_from;        // where that came from
  bool method_measures = false;  // the method estimates it frame by frame (sparse)
  // Unset without the pipe's radius (planar dense methods can run without it).
  std::optional<WallDistanceObservability> observability;
};

// The start camera's distance to the wall it faces (m) when no method measured it: the focal
// length over the dataset's reference scale where that lies within the pipe's diameter, else the
// radius (the camera on the axis).
double NominalStartWallDistance(const DatasetManifest& manifest, const Camera& camera,
                                double radius_m);

// `start_from` names the source; `radius_m` 0: no observability.
WallDistanceStatement MakeWallDistanceStatement(const Camera& camera, const CameraMount& mount,
                                                double radius_m, double start_m,
                                                std::string start_from, bool method_measures);

// Whether the run's scale rests on the measurement (the method measures and the view sees it).
bool WallDistanceMeasured(const WallDistanceStatement& statement);

nlohmann::json WallDistanceJson(const WallDistanceStatement& statement);

// The farthest any pose of `poses` (pipe frame, axis Z) is across the pipe from the first, m.
double CrossSectionExcursion(const Trajectory& poses);

// Where the view cannot measure the wall distance, a run whose camera strays more than
// `limit_share` of that distance across the pipe has a scale that follows an excursion the images
// could not confirm: the reason that makes it unreliable; empty when the view measures the
// distance, the limit is 0 or the camera kept within it.
std::string UnobservedExcursionReason(const WallDistanceStatement& statement, double excursion_m,
                                      double limit_share);

// One line for the run's warnings when the wall distance is assumed, empty when it is measured.
std::string WallDistanceWarning(const WallDistanceStatement& statement, const std::string& method);

}  // namespace pipescope
