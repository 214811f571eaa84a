#include "pipescope/mapping/dense_appearance_ply.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#include "pipescope/util/atomic_file.h"
#include "pipescope/util/error.h"

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

// The header up to the vertex count, and from after it.
std::string HeaderStart(const std::string& comment) {
  return "ply\nformat binary_little_endian 1.0\ncomment " + comment + "\nelement vertex ";
}
const char kHeaderEnd[] =
    "\nproperty float x\nproperty float y\nproperty float z\n"
    "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";

void AppendVertices(const std::vector<DenseMapPoint>& points, std::string* bytes) {
  bytes->reserve(bytes->size() + points.size() * (3 * sizeof(float) + 3));
  for (const DenseMapPoint& point : points) {
    for (int k = 0; k < 3; ++k) {
      AppendFloatLittleEndian(static_cast<float>(point.position[k]), bytes);
    }
    bytes->append(3, static_cast<char>(GreyByte(point.grey)));
  }
}

// The count padded with spaces to a fixed width, which PLY readers skip as they split words.
constexpr int kCountWidth = 20;

}  // namespace

void WriteDenseAppearancePly(const std::filesystem::path& path,
                             const std::vector<DenseMapPoint>& points, const std::string& comment) {
  std::string bytes = HeaderStart(comment) + std::to_string(points.size()) + kHeaderEnd;
  AppendVertices(points, &bytes);
  // Writes the string's bytes unchanged (binary mode), NULs included.
  WriteTextFileAtomically(path, bytes);
}

DenseAppearancePlyWriter::DenseAppearancePlyWriter(const std::filesystem::path& path,
                                                   const std::string& comment)
    : path_(path), out_(path, std::ios::binary | std::ios::trunc) {
  if (!out_) throw InputError(path.string() + ": cannot be written");
  out_ << HeaderStart(comment);
  count_position_ = out_.tellp();
  out_ << std::string(kCountWidth, ' ') << kHeaderEnd;
}

void DenseAppearancePlyWriter::Append(const std::vector<DenseMapPoint>& points) {
  std::string bytes;
  AppendVertices(points, &bytes);
  out_.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  points_ += static_cast<std::int64_t>(points.size());
}

void DenseAppearancePlyWriter::Close() {
  out_.seekp(count_position_);
  out_ << std::to_string(points_);
  out_.close();
  if (!out_) throw InputError(path_.string() + ": write failed");
}

}  // namespace pipescope
