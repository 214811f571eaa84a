#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace pipescope {

using PlyColour = std::array<std::uint8_t, 3>;  // red, green, blue

// Writes `points` (metres) as an ASCII PLY point cloud (vertex x, y, z as double), atomically.
// `colours`: empty, or one per point (then red, green, blue uchar properties follow); `comment`
// goes into the header.
void WritePlyPoints(const std::filesystem::path& path, const std::vector<Eigen::Vector3d>& points,
                    const std::vector<PlyColour>& colours = {},
                    const std::string& comment = "pipescope point cloud, metres, pipe frame");

}  // namespace pipescope
