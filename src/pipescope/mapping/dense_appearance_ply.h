#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "pipescope/mapping/dense_appearance_map.h"

namespace pipescope {

// Writes the points of a dense appearance map (001 §IV-B; points_dense.ply of a run) as a
// binary little-endian PLY point cloud, atomically: x, y, z as float (metres) and red = green =
// blue = the grey value rounded and clamped to 0..255 (uchar), which point-cloud viewers show as
// grey. Binary because a route holds millions of points; io/point_cloud_ply writes ASCII only.
void WriteDenseAppearancePly(const std::filesystem::path& path,
                             const std::vector<DenseMapPoint>& points,
                             const std::string& comment = "pipescope dense appearance map, metres");

// The same file written piece by piece, so a long route never holds all its points: the header
// leaves room for the vertex count, which Close() fills in. Not atomic: for a file in a run's
// staging folder, which only a finished run publishes.
class DenseAppearancePlyWriter {
 public:
  // Creates (truncates) `path`; throws InputError naming it when it cannot be opened.
  DenseAppearancePlyWriter(const std::filesystem::path& path,
                           const std::string& comment = "pipescope dense appearance map, metres");
  void Append(const std::vector<DenseMapPoint>& points);
  // Writes the vertex count and closes the file; throws InputError naming it on a write error.
  void Close();
  std::int64_t points() const { return points_; }

 private:
  std::filesystem::path path_;
  std::ofstream out_;
  std::streampos count_position_;
  std::int64_t points_ = 0;
};

}  // namespace pipescope
