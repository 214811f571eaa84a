#include "pipescope/io/junctions.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <set>

#include "pipescope/util/atomic_file.h"
#include "pipescope/util/error.h"

namespace pipescope {
namespace {

// "file:line: key" for error messages; yaml-cpp counts lines from 0.
std::string Where(const std::filesystem::path& path, const YAML::Node& node,
                  const std::string& key) {
  std::string where = path.string();
  if (node.Mark().line >= 0) where += ":" + std::to_string(node.Mark().line + 1);
  return where + ": " + key;
}

double ReadFiniteDouble(const std::filesystem::path& path, const YAML::Node& node,
                        const std::string& key) {
  double value = 0;
  if (!node.IsScalar() || !YAML::convert<double>::decode(node, value) || !std::isfinite(value)) {
    throw InputError(Where(path, node, key) + " must be a finite number");
  }
  return value;
}

// A list [x, y, z] of finite numbers at `node` (named `key` in messages).
Eigen::Vector3d ReadVector(const std::filesystem::path& path, const YAML::Node& node,
                           const std::string& key) {
  if (!node.IsSequence() || node.size() != 3) {
    throw InputError(Where(path, node, key) + " must be a list [x, y, z]");
  }
  Eigen::Vector3d vector;
  for (int i = 0; i < 3; ++i) {
    vector[i] = ReadFiniteDouble(path, node[i], key + "[" + std::to_string(i) + "]");
  }
  return vector;
}

Eigen::Vector3d ReadCenter(const std::filesystem::path& path, const YAML::Node& entry,
                           const std::string& key) {
  // A missing key yields an invalid node that cannot be reassigned, so choose the key first.
  const bool has_center_m = !entry["center"] && entry["center_m"];
  const std::string center_key = key + (has_center_m ? ".center_m" : ".center");
  const YAML::Node node = entry[has_center_m ? "center_m" : "center"];
  if (!node) throw InputError(Where(path, entry, key) + ": missing key `center`");
  return ReadVector(path, node, center_key);
}

std::vector<Eigen::Vector3d> ReadAxes(const std::filesystem::path& path, const YAML::Node& entry,
                                      const std::string& key) {
  std::vector<Eigen::Vector3d> axes;
  const YAML::Node node = entry["axes"];
  if (!node) return axes;
  if (!node.IsSequence()) throw InputError(Where(path, node, key + ".axes") + " must be a list");
  for (std::size_t i = 0; i < node.size(); ++i) {
    const std::string axis_key = key + ".axes[" + std::to_string(i) + "]";
    const Eigen::Vector3d axis = ReadVector(path, node[i], axis_key);
    if (!(axis.norm() > 0.0)) throw InputError(Where(path, node[i], axis_key) + " is zero");
    axes.push_back(axis.normalized());
  }
  return axes;
}

std::vector<Junction> ReadJunctions(const std::filesystem::path& path, bool with_timestamps) {
  const std::string text = ReadTextFile(path);
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& error) {
    throw InputError(path.string() + ":" + std::to_string(error.mark.line + 1) +
                     ": invalid YAML: " + error.msg);
  }
  std::vector<Junction> junctions;
  if (!root.IsMap() || !root["junctions"]) {
    if (with_timestamps) throw InputError(path.string() + ": missing key `junctions`");
    return junctions;  // A scene without junctions, e.g. a straight pipe.
  }
  const YAML::Node list = root["junctions"];
  if (list.IsNull()) return junctions;
  if (!list.IsSequence()) throw InputError(Where(path, list, "junctions") + " must be a list");
  std::set<std::string> names;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const YAML::Node entry = list[i];
    const std::string key = "junctions[" + std::to_string(i) + "]";
    if (!entry.IsMap()) throw InputError(Where(path, entry, key) + " must be a map");
    Junction junction;
    const YAML::Node name = entry["name"];
    if (!name || !name.IsScalar() || name.Scalar().empty()) {
      throw InputError(Where(path, entry, key) + ": missing or empty key `name`");
    }
    junction.name = name.Scalar();
    // Scene names identify junctions in junction_distances, so they must be unique.
    if (!with_timestamps && !names.insert(junction.name).second) {
      throw InputError(Where(path, name, key + ".name") + ": duplicate junction name '" +
                       junction.name + "'");
    }
    if (with_timestamps) {
      const YAML::Node timestamp = entry["timestamp"];
      if (!timestamp) throw InputError(Where(path, entry, key) + ": missing key `timestamp`");
      junction.timestamp = ReadFiniteDouble(path, timestamp, key + ".timestamp");
    }
    junction.center = ReadCenter(path, entry, key);
    if (with_timestamps) junction.axes = ReadAxes(path, entry, key);
    junctions.push_back(junction);
  }
  return junctions;
}

}  // namespace

std::vector<Junction> ReadSceneJunctions(const std::filesystem::path& scene_yaml) {
  return ReadJunctions(scene_yaml, /*with_timestamps=*/false);
}

std::vector<Junction> ReadEstimatedJunctions(const std::filesystem::path& junctions_yaml) {
  return ReadJunctions(junctions_yaml, /*with_timestamps=*/true);
}

void WriteEstimatedJunctions(const std::filesystem::path& junctions_yaml,
                             const std::vector<Junction>& junctions) {
  YAML::Emitter out;
  // 17 significant digits round-trip doubles exactly.
  out.SetDoublePrecision(17);
  out << YAML::BeginMap << YAML::Key << "junctions" << YAML::Value << YAML::BeginSeq;
  for (const Junction& junction : junctions) {
    out << YAML::BeginMap;
    out << YAML::Key << "name" << YAML::Value << junction.name;
    if (std::isfinite(junction.timestamp)) {
      out << YAML::Key << "timestamp" << YAML::Value << junction.timestamp;
    }
    out << YAML::Key << "center" << YAML::Value << YAML::Flow << YAML::BeginSeq
        << junction.center.x() << junction.center.y() << junction.center.z() << YAML::EndSeq;
    if (!junction.axes.empty()) {
      out << YAML::Key << "axes" << YAML::Value << YAML::Flow << YAML::BeginSeq;
      for (const Eigen::Vector3d& axis : junction.axes) {
        out << YAML::BeginSeq << axis.x() << axis.y() << axis.z() << YAML::EndSeq;
      }
      out << YAML::EndSeq;
    }
    out << YAML::EndMap;
  }
  out << YAML::EndSeq << YAML::EndMap;
  WriteTextFileAtomically(junctions_yaml, std::string(out.c_str()) + "\n");
}

}  // namespace pipescope
