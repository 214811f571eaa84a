#pragma once

#include <filesystem>
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

}  // namespace pipescope
