#include "pipescope/pipeline/pipe_plan_yaml.h"

#include <vector>

#include "pipescope/io/yaml_helpers.h"
#include "pipescope/util/error.h"

namespace pipescope {
namespace {

Eigen::Vector3d Vector(const YAML::Node& root, const std::string& key,
                       const std::filesystem::path& file) {
  const std::vector<double> values = RequiredYamlValue<std::vector<double>>(root, key, file);
  if (values.size() != 3 || !Eigen::Vector3d(values[0], values[1], values[2]).allFinite()) {
    throw InputError(file.string() + ": key '" + key + "' must be a list [x, y, z] of numbers");
  }
  return {values[0], values[1], values[2]};
}

}  // namespace

std::optional<PipePlan> ReadPipePlan(const std::filesystem::path& scene_yaml,
                                     const Eigen::Vector3d& up, std::string* why_not) {
  const YAML::Node root = LoadYamlFile(scene_yaml);
  if (!FindYamlKey(root, "route_start").IsDefined()) {
    *why_not = scene_yaml.string() + " has no route_start (where the run started)";
    return std::nullopt;
  }
  PipePlan plan;
  plan.up = up;
  plan.start_position = Vector(root, "route_start.position", scene_yaml);
  plan.start_heading = Vector(root, "route_start.heading", scene_yaml);
  const std::optional<double> radius = OptionalYamlValue<double>(root, "radius", scene_yaml);
  const YAML::Node sections = root["sections"];
  if (!sections || !sections.IsSequence()) {
    throw InputError(scene_yaml.string() + ": key 'sections' must be a list");
  }
  for (std::size_t i = 0; i < sections.size(); ++i) {
    const YAML::Node& section = sections[i];
    const std::string key = "sections[" + std::to_string(i) + "]";
    const std::string type = RequiredYamlValue<std::string>(section, "type", scene_yaml);
    if (type == "straight") {
      const std::optional<double> own = OptionalYamlValue<double>(section, "radius", scene_yaml);
      if (!own && !radius) {
        throw InputError(scene_yaml.string() + ": " + key + " has no radius, nor has the file");
      }
      plan.pipes.push_back({Vector(section, "start", scene_yaml),
                            Vector(section, "end", scene_yaml), own ? *own : *radius});
    } else if (type == "tee") {
      plan.tees.push_back({RequiredYamlValue<std::string>(section, "name", scene_yaml),
                           Vector(section, "center", scene_yaml)});
    } else {
      *why_not = scene_yaml.string() + ": " + key + " is a " + type +
                 "; loop closure knows networks of straight pipes and tees";
      return std::nullopt;
    }
  }
  if (plan.tees.empty()) {
    *why_not = scene_yaml.string() + " has no tee: there is no junction to count turns at";
    return std::nullopt;
  }
  return plan;
}

}  // namespace pipescope
