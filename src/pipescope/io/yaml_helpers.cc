#include "pipescope/io/yaml_helpers.h"

#include <sstream>

namespace pipescope {

YAML::Node LoadYamlFile(const std::filesystem::path& path) {
  if (!std::filesystem::is_regular_file(path)) {
    throw InputError("file not found: " + path.string());
  }
  try {
    return YAML::LoadFile(path.string());
  } catch (const YAML::Exception& error) {
    throw InputError(path.string() + ": not valid YAML: " + error.what());
  }
}

YAML::Node FindYamlKey(const YAML::Node& root, const std::string& dotted_key) {
  // yaml-cpp's operator[] on a const node never inserts; Node copies share data, so walk with
  // fresh handles via reset().
  YAML::Node node;
  node.reset(root);
  std::stringstream parts(dotted_key);
  std::string part;
  while (std::getline(parts, part, '.')) {
    if (!node.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
    const YAML::Node child = static_cast<const YAML::Node&>(node)[part];
    if (!child.IsDefined()) return YAML::Node(YAML::NodeType::Undefined);
    node.reset(child);
  }
  return node;
}

}  // namespace pipescope
