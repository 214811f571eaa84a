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

// A point cloud read back: positions and, when the file has red/green/blue, one colour each.
struct PlyPoints {
  std::vector<Eigen::Vector3d> points;
  std::vector<PlyColour> colours;
};

// Reads an ASCII PLY point cloud whose vertex element has x, y, z (float or double) and
// optionally red, green, blue (uchar), in any order with other scalar properties. Throws
// InputError naming the file for another format or a malformed line.
PlyPoints ReadPlyPoints(const std::filesystem::path& path);

}  // namespace pipescope
