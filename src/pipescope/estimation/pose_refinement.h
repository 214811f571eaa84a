#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "pipescope/estimation/track_statistics.h"

namespace pipescope {

// The per-frame six-degree-of-freedom refinement of 000 §5.3.3: one key frame's pose
// (quaternion rotation and position) moved by Levenberg-Marquardt to minimise eq. 42 against the
// statistics S(g) of its points' tracks, with the frame's own contributions taken out.
struct PoseRefinementOptions {
  // Huber loss scale on a point's surface distance from its track's mean (metres); 0 = plain
  // least squares, as 000.
  double huber_m = 0.0005;
  int max_iterations = 20;
  // A refinement that moves the camera further than this fraction of the radius is not taken
  // (0: any). It corrects a pose the window adjustment already placed; a key frame that sees
  // too little of the wall (faint, noisy texture) was moved up to the whole radius across the
  // pipe by it (docs/conditions.md).
  double max_position_change_radii = 0.025;
};

struct SurfaceObservation {
  Eigen::Vector3d bearing;  // camera frame
  TrackStatistics track;    // n > 0, without this frame's contribution
};

// Returns the refined world_from_cam; `initial` when there are fewer than 6 observations, Ceres
// fails, or the camera would move too far.
Eigen::Isometry3d RefinePoseOnSurface(const Eigen::Isometry3d& initial,
                                      const std::vector<SurfaceObservation>& observations,
                                      double radius_m, double phi_reference_rad,
                                      const PoseRefinementOptions& options);

}  // namespace pipescope
