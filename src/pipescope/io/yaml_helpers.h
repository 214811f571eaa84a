#pragma once

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <optional>
#include <string>

#include "pipescope/util/error.h"

namespace pipescope {

// Parses a YAML file; throws InputError naming the file when it is missing or malformed.
YAML::Node LoadYamlFile(const std::filesystem::path& path);

// Looks up a dotted key ("pipe.inner_radius_m") below `root`; an undefined node when absent.
YAML::Node FindYamlKey(const YAML::Node& root, const std::string& dotted_key);

// Converts the value at `dotted_key` to T, or returns nullopt when the key is absent. Throws
// InputError naming the file and key when the value has the wrong type.
template <typename T>
std::optional<T> OptionalYamlValue(const YAML::Node& root, const std::string& dotted_key,
                                   const std::filesystem::path& file) {
  const YAML::Node node = FindYamlKey(root, dotted_key);
  if (!node.IsDefined() || node.IsNull()) return std::nullopt;
  try {
    return node.as<T>();
  } catch (const YAML::Exception&) {
    throw InputError(file.string() + ": key '" + dotted_key + "' has an invalid value");
  }
}

// Like OptionalYamlValue, but a missing key is an InputError naming the file and key.
template <typename T>
T RequiredYamlValue(const YAML::Node& root, const std::string& dotted_key,
                    const std::filesystem::path& file) {
  std::optional<T> value = OptionalYamlValue<T>(root, dotted_key, file);
  if (!value) throw InputError(file.string() + ": required key '" + dotted_key + "' is missing");
  return *value;
}

}  // namespace pipescope
