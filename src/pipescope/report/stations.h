#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "pipescope/io/dataset.h"
#include "pipescope/io/trajectory.h"

namespace pipescope {

// Inspection coordinates of a run (GUIDE §4, docs/formats.md): each localised frame's distance
// along the pipe from the run's start and the camera's roll as a clock angle.

// Where "along the pipe" runs.
enum class SurveyLine {
  // A straight pipe in the pipe frame (odometry runs): its axis is Z; distance is the camera's
  // position along it, positive in the direction the camera first moved (the survey direction,
  // kept when the crawler turns back, so a place keeps its distance and its clock position).
  kStraightAxis,
  // A network mapped in the first camera's frame (map runs): distance is the path travelled,
  // each step projected on the local direction of the path (the chord over `path_window_m`
  // either side), so the crawler's sideways wander does not add to it.
  kTravelledPath,
};

struct StationOptions {
  SurveyLine line = SurveyLine::kStraightAxis;
  Eigen::Vector3d up = Eigen::Vector3d(0.0, -1.0, 0.0);  // 12 o'clock, in the trajectory's frame
  double path_window_m = 0.1;
};

struct Station {
  int frame = -1;  // index of the frame in the dataset
  double timestamp = 0.0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d travel = Eigen::Vector3d::UnitZ();  // unit: the survey direction here
  double distance_m = 0.0;
  double speed_m_s = 0.0;       // along the pipe, signed: negative while the crawler backs up
  double roll_clock_deg = 0.0;  // the camera's upright as a clock angle; NaN where undefined
};

// The stations of `trajectory`, whose i-th pose shows dataset frame `frames[i]` (equal sizes).
std::vector<Station> ComputeStations(const Trajectory& trajectory, const std::vector<int>& frames,
                                     const StationOptions& options);

// The dataset frame of each pose, by timestamp: the nearest time of the timestamps file, or
// round(t * fps). -1 for a pose between frames (more than a third of a frame period off).
std::vector<int> FrameIndicesByTime(const Trajectory& trajectory, const DatasetManifest& manifest);

// stations.csv: frame, timestamp_s, distance_m, roll_clock_deg, roll_clock, speed_m_s.
void WriteStationsCsv(const std::filesystem::path& path, const std::vector<Station>& stations);
// Reads a stations.csv back: frame, timestamp, distance, roll and speed of each row (positions
// and directions are not in the file). InputError naming the file and line when malformed.
std::vector<Station> ReadStationsCsv(const std::filesystem::path& path);

const char* SurveyLineName(SurveyLine line);
// Inverse of SurveyLineName; InputError naming `context` for another name.
SurveyLine ParseSurveyLine(const std::string& name, const std::string& context);

}  // namespace pipescope
