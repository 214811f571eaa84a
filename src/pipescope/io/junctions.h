#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

namespace pipescope {

// A pipe junction (T-intersection): its name, its centre in the world frame (metres) and, for
// estimated junctions, the time at which the camera passed it.
struct Junction {
  std::string name;
  double timestamp = std::numeric_limits<double>::quiet_NaN();
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  // For estimated junctions, optional: the unit directions of the pipes that meet there, each
  // pointing from the centre along its pipe (001 §III-D: the red and the blue axis).
  std::vector<Eigen::Vector3d> axes;
};

// Reads the junctions of a scene.yaml: key `junctions`, a list of {name, center: [x, y, z]}
// (`center_m` is accepted for `center`). A scene without the key has no junctions. Timestamps
// are NaN. Names must be unique. Throws InputError naming the file and key at fault.
std::vector<Junction> ReadSceneJunctions(const std::filesystem::path& scene_yaml);

// Reads a junctions.yaml written by a run: key `junctions`, a list of
// {name, timestamp, center: [x, y, z]} with optional `axes: [[x, y, z], ...]` (non-zero, read
// as unit vectors). Throws InputError naming the file and key at fault.
std::vector<Junction> ReadEstimatedJunctions(const std::filesystem::path& junctions_yaml);

// Writes a junctions.yaml that ReadEstimatedJunctions reads back exactly, atomically. A NaN
// timestamp and empty axes are left out.
void WriteEstimatedJunctions(const std::filesystem::path& junctions_yaml,
                             const std::vector<Junction>& junctions);

}  // namespace pipescope
