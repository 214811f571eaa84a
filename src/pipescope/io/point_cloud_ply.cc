#include "pipescope/io/point_cloud_ply.h"

#include <cstdio>
#include <stdexcept>

#include "pipescope/util/atomic_file.h"

namespace pipescope {

void WritePlyPoints(const std::filesystem::path& path, const std::vector<Eigen::Vector3d>& points,
                    const std::vector<PlyColour>& colours, const std::string& comment) {
  if (!colours.empty() && colours.size() != points.size()) {
    throw std::invalid_argument("WritePlyPoints: one colour per point or none");
  }
  std::string text = "ply\nformat ascii 1.0\ncomment " + comment + "\n";
  text += "element vertex " + std::to_string(points.size()) + "\n";
  text += "property double x\nproperty double y\nproperty double z\n";
  if (!colours.empty()) text += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  text += "end_header\n";
  char line[160];
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d& p = points[i];
    std::snprintf(line, sizeof(line), "%.9g %.9g %.9g", p.x(), p.y(), p.z());
    text += line;
    if (!colours.empty()) {
      std::snprintf(line, sizeof(line), " %d %d %d", colours[i][0], colours[i][1], colours[i][2]);
      text += line;
    }
    text += '\n';
  }
  WriteTextFileAtomically(path, text);
}

}  // namespace pipescope
