#include "pipescope/io/point_cloud_ply.h"

#include <cstdio>
#include <string>

#include "pipescope/util/atomic_file.h"

namespace pipescope {

void WritePlyPoints(const std::filesystem::path& path, const std::vector<Eigen::Vector3d>& points) {
  std::string text = "ply\nformat ascii 1.0\ncomment pipescope point cloud, metres, pipe frame\n";
  text += "element vertex " + std::to_string(points.size()) + "\n";
  text += "property double x\nproperty double y\nproperty double z\nend_header\n";
  char line[128];
  for (const Eigen::Vector3d& p : points) {
    std::snprintf(line, sizeof(line), "%.9g %.9g %.9g\n", p.x(), p.y(), p.z());
    text += line;
  }
  WriteTextFileAtomically(path, text);
}

}  // namespace pipescope
