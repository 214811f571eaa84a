#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <vector>

namespace pipescope {

// Writes `points` (metres) as an ASCII PLY point cloud (vertex x, y, z as double), atomically.
void WritePlyPoints(const std::filesystem::path& path, const std::vector<Eigen::Vector3d>& points);

}  // namespace pipescope
