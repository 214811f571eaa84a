#include "pipescope/synthetic/simulation_yaml.h"

#include <yaml-cpp/yaml.h>

#include <string>

#include "pipescope/synthetic/presets.h"
#include "pipescope/util/error.h"

namespace pipescope {

SimulationConfig ReadSimulationConfig(const std::filesystem::path& path) {
  const std::string name = path.string();
  YAML::Node root;
  try {
    root = YAML::LoadFile(name);
  } catch (const YAML::Exception& error) {
    throw InputError(name + ": not readable as YAML: " + error.what());
  }
  if (!root.IsMap()) throw InputError(name + ": expected a map of simulation keys");
  try {
    const YAML::Node preset = root["preset"];
    if (!preset || !preset.IsScalar()) throw InputError("key 'preset' missing");
    SimulationConfig config = PresetConfig(preset.as<std::string>());
    for (const auto& entry : root) {
      const std::string key = entry.first.as<std::string>();
      if (key == "preset") continue;
      if (!entry.second.IsScalar()) throw InputError("key '" + key + "' is not a single value");
      SetConfigValue(&config, key + "=" + entry.second.as<std::string>());
    }
    ValidateConfig(config);
    return config;
  } catch (const InputError& error) {
    throw InputError(name + ": " + error.what());
  }
}

}  // namespace pipescope
