#pragma once

#include <filesystem>
#include <string>

#include "pipescope/synthetic/simulation_config.h"

namespace pipescope {

struct SimulationSummary {
  int frames = 0;
  double seconds = 0.0;         // wall-clock rendering time
  double route_length_m = 0.0;  // the scene's whole route
  double travelled_m = 0.0;     // the path the rendered frames cover
  // Of a one-way run: how much of the route's centreline is left beyond the last frame (0 when
  // the robot reached the route's end), and how far along it the robot drove.
  double route_left_m = 0.0;
  double route_driven_m = 0.0;
};

// Renders the dataset `config` describes into `out` (GUIDE §4): images/, camera.yaml,
// groundtruth.tum, scene.yaml, white_card/, gain_mask.png, simulation.yaml (every key, for
// provenance) and dataset.yaml; layout scale-target adds target.yaml. Everything is written into a
// temporary sibling folder that is renamed onto `out` at the end, so a failed or interrupted run
// leaves nothing half written. `out` may be missing, empty, or an earlier simulated dataset (it is
// replaced); any other existing folder is an InputError. Layout checkerboard writes a calibration
// dataset instead (checkerboard.h).
SimulationSummary SimulateDataset(const SimulationConfig& config, const std::filesystem::path& out);

// simulation.yaml: every key of `config`, for provenance and as the mark of a simulated dataset.
std::string SimulationConfigYaml(const SimulationConfig& config);

}  // namespace pipescope
