#pragma once

#include <filesystem>

#include "pipescope/synthetic/simulation_config.h"

namespace pipescope {

// Reads back the simulation.yaml a simulated dataset carries (every key, as `pipescope
// simulate` wrote it): the preset's config with each key set as recorded, then validated, so
// that Simulation(config) renders the dataset's scene, texture and motion again. Throws
// InputError naming the file (and the key) for an unreadable file, a value that is not a
// scalar, an unknown preset or key, or a bad value.
SimulationConfig ReadSimulationConfig(const std::filesystem::path& path);

}  // namespace pipescope
