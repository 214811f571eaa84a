#include "pipescope/synthetic/scene_yaml.h"

#include <yaml-cpp/yaml.h>

#include <numbers>
#include <stdexcept>
#include <string>

#include "pipescope/util/atomic_file.h"

namespace pipescope {
namespace {

void EmitVector(YAML::Emitter& out, const char* key, const Eigen::Vector3d& value) {
  out << YAML::Key << key << YAML::Value << YAML::Flow << YAML::BeginSeq << value.x() << value.y()
      << value.z() << YAML::EndSeq;
}

}  // namespace

void WriteSceneYaml(const std::filesystem::path& path, const Scene& scene,
                    const std::optional<RouteStart>& route_start) {
  if (scene.sections().empty()) {
    throw std::invalid_argument("WriteSceneYaml: the scene has no sections");
  }
  YAML::Emitter out;
  // 17 significant digits round-trip doubles exactly.
  out.SetDoublePrecision(17);
  out << YAML::BeginMap;
  out << YAML::Key << "radius" << YAML::Value << scene.sections().front().radius;
  out << YAML::Key << "sections" << YAML::Value << YAML::BeginSeq;
  for (const Scene::Entry& entry : scene.entries()) {
    out << YAML::BeginMap;
    if (entry.is_tee) {
      const Scene::Junction& junction = scene.junctions()[entry.index];
      out << YAML::Key << "type" << YAML::Value << "tee";
      out << YAML::Key << "name" << YAML::Value << junction.name;
      EmitVector(out, "center", junction.center);
    } else {
      const PipeSection& section = scene.sections()[entry.index];
      if (section.type == SectionType::kStraight) {
        out << YAML::Key << "type" << YAML::Value << "straight";
        EmitVector(out, "start", section.start);
        EmitVector(out, "end", section.EndPoint());
      } else {
        out << YAML::Key << "type" << YAML::Value << "bend";
        EmitVector(out, "start", section.start);
        EmitVector(out, "end", section.EndPoint());
        EmitVector(out, "center", section.bend_center);
        EmitVector(out, "axis", section.bend_axis);
        out << YAML::Key << "bend_radius" << YAML::Value << section.bend_radius;
        out << YAML::Key << "angle_deg" << YAML::Value
            << section.bend_angle * 180 / std::numbers::pi;
      }
      out << YAML::Key << "radius" << YAML::Value << section.radius;
    }
    out << YAML::EndMap;
  }
  out << YAML::EndSeq;
  out << YAML::Key << "junctions" << YAML::Value << YAML::BeginSeq;
  for (const Scene::Junction& junction : scene.junctions()) {
    out << YAML::BeginMap;
    out << YAML::Key << "name" << YAML::Value << junction.name;
    EmitVector(out, "center", junction.center);
    out << YAML::EndMap;
  }
  out << YAML::EndSeq;
  if (route_start) {
    out << YAML::Key << "route_start" << YAML::Value << YAML::BeginMap;
    EmitVector(out, "position", route_start->position);
    EmitVector(out, "heading", route_start->heading);
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
  WriteTextFileAtomically(path, std::string(out.c_str()) + "\n");
}

}  // namespace pipescope
