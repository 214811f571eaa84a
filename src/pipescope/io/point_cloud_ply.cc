#include "pipescope/io/point_cloud_ply.h"

#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "pipescope/util/atomic_file.h"
#include "pipescope/util/error.h"

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

PlyPoints ReadPlyPoints(const std::filesystem::path& path) {
  std::ifstream in(path);
  const auto fail = [&](const std::string& why) { return InputError(path.string() + ": " + why); };
  if (!in) throw fail("cannot be read");
  std::string line;
  if (!std::getline(in, line) || line != "ply") throw fail("not a PLY file");
  long long count = -1;
  std::vector<std::string> properties;  // of the vertex element, in order
  bool in_vertex = false;
  while (std::getline(in, line) && line != "end_header") {
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (keyword == "format") {
      std::string format;
      words >> format;
      if (format != "ascii") throw fail("only ASCII PLY files are read (format " + format + ")");
    } else if (keyword == "element") {
      std::string name;
      long long n = 0;
      words >> name >> n;
      in_vertex = name == "vertex";
      if (in_vertex) count = n;
    } else if (keyword == "property" && in_vertex) {
      std::string type, name;
      words >> type >> name;
      if (type == "list") throw fail("vertex list properties are not read");
      properties.push_back(name);
    }
  }
  if (line != "end_header" || count < 0) throw fail("no vertex element before end_header");
  const auto index_of = [&](const std::string& name) {
    for (std::size_t i = 0; i < properties.size(); ++i)
      if (properties[i] == name) return static_cast<int>(i);
    return -1;
  };
  const int x = index_of("x"), y = index_of("y"), z = index_of("z");
  const int r = index_of("red"), g = index_of("green"), b = index_of("blue");
  if (x < 0 || y < 0 || z < 0) throw fail("the vertices have no x, y, z");
  const bool coloured = r >= 0 && g >= 0 && b >= 0;
  PlyPoints cloud;
  cloud.points.reserve(count);
  std::vector<double> values(properties.size());
  for (long long i = 0; i < count; ++i) {
    if (!std::getline(in, line)) throw fail("ends after " + std::to_string(i) + " vertices");
    std::istringstream numbers(line);
    for (double& value : values) {
      if (!(numbers >> value)) throw fail("malformed vertex " + std::to_string(i));
    }
    cloud.points.emplace_back(values[x], values[y], values[z]);
    if (coloured) {
      cloud.colours.push_back({static_cast<std::uint8_t>(values[r]),
                               static_cast<std::uint8_t>(values[g]),
                               static_cast<std::uint8_t>(values[b])});
    }
  }
  return cloud;
}

}  // namespace pipescope
