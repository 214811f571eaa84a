#pragma once

#include <string>
#include <vector>

#include "pipescope/synthetic/simulation_config.h"

namespace pipescope {

// The presets, each following one of the papers' set-ups (see each one's description).
const std::vector<std::string>& PresetNames();

// The configuration of a preset; throws InputError naming --preset for an unknown name.
SimulationConfig PresetConfig(const std::string& name);

}  // namespace pipescope
