#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "pipescope/io/trajectory.h"
#include "pipescope/report/stations.h"

namespace pipescope {

// A run directory read back for `locate` and `report`: run.json, the trajectory and its
// stations (recomputed from trajectory.tum, stations.csv's frames and run.json's `inspection`,
// so that positions and directions are at hand; the distances equal the file's).
struct RunFiles {
  std::filesystem::path dir;
  nlohmann::json run_json;
  std::string command;  // "odometry" | "map"
  Trajectory trajectory;
  std::vector<Station> stations;  // one per pose of `trajectory`
  StationOptions station_options;
  std::string up_source;
  double radius_m = 0.0;

  // The station of dataset frame `frame`, or nullptr when that frame has no pose.
  const Station* StationOfFrame(int frame) const;
  // A file of the run, or nothing when the run has none.
  std::optional<std::filesystem::path> File(const std::string& name) const;
};

// Throws InputError naming the run directory and the file missing or malformed (a run written
// before inspection coordinates existed has no stations.csv: run it again).
RunFiles ReadRunFiles(const std::filesystem::path& run_dir);

}  // namespace pipescope
