#include "pipescope/mapping/dense_appearance_ply.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#include "pipescope/util/atomic_file.h"

namespace pipescope {
namespace {

// Little-endian whatever the host's byte order, as the header declares.
void AppendFloatLittleEndian(float value, std::string* out) {
  const std::uint32_t bits = std::bit_cast<std::uint32_t>(value);
  for (int shift = 0; shift < 32; shift += 8) out->push_back(static_cast<char>(bits >> shift));
}

std::uint8_t GreyByte(float grey) {
  if (!std::isfinite(grey)) return 0;
  return static_cast<std::uint8_t>(std::lround(std::clamp(grey, 0.0f, 255.0f)));
}

}  // namespace

void WriteDenseAppearancePly(const std::filesystem::path& path,
                             const std::vector<DenseMapPoint>& points, const std::string& comment) {
  std::string bytes = "ply\nformat binary_little_endian 1.0\ncomment " + comment + "\n";
  bytes += "element vertex " + std::to_string(points.size()) + "\n";
  bytes += "property float x\nproperty float y\nproperty float z\n";
  bytes += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  bytes += "end_header\n";
  bytes.reserve(bytes.size() + points.size() * (3 * sizeof(float) + 3));
  for (const DenseMapPoint& point : points) {
    for (int k = 0; k < 3; ++k) {
      AppendFloatLittleEndian(static_cast<float>(point.position[k]), &bytes);
    }
    const char grey = static_cast<char>(GreyByte(point.grey));
    bytes.append(3, grey);
  }
  // Writes the string's bytes unchanged (binary mode), NULs included.
  WriteTextFileAtomically(path, bytes);
}

}  // namespace pipescope
