#include "pipescope/io/trajectory.h"

#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <string_view>

#include "pipescope/util/atomic_file.h"
#include "pipescope/util/error.h"

namespace pipescope {
namespace {

constexpr int kTumFields = 8;  // timestamp tx ty tz qx qy qz qw
// A quaternion shorter than this carries no rotation to normalise.
constexpr double kMinQuaternionNorm = 1e-9;

std::string Where(const std::filesystem::path& path, int line_number) {
  return path.string() + ":" + std::to_string(line_number);
}

bool IsSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

// Splits on white space; std::from_chars ignores the locale, unlike strtod and streams.
std::vector<std::string_view> SplitFields(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && IsSpace(line[i])) ++i;
    const std::size_t begin = i;
    while (i < line.size() && !IsSpace(line[i])) ++i;
    if (i > begin) fields.push_back(line.substr(begin, i - begin));
  }
  return fields;
}

bool ParseDouble(std::string_view text, double* value) {
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  const char* end = text.data() + text.size();
  const auto [ptr, error] = std::from_chars(text.data(), end, *value);
  return error == std::errc() && ptr == end;
}

}  // namespace

Trajectory ReadTumTrajectory(const std::filesystem::path& path) {
  std::istringstream stream(ReadTextFile(path));
  Trajectory trajectory;
  std::string line;
  int line_number = 0;
  while (std::getline(stream, line)) {
    ++line_number;
    std::string_view content = line;
    if (const std::size_t hash = content.find('#'); hash != std::string_view::npos) {
      content = content.substr(0, hash);
    }
    const std::vector<std::string_view> fields = SplitFields(content);
    if (fields.empty()) continue;
    if (fields.size() != kTumFields) {
      throw InputError(Where(path, line_number) +
                       ": expected 8 values `timestamp tx ty tz qx qy qz qw`, found " +
                       std::to_string(fields.size()));
    }
    std::array<double, kTumFields> values;
    for (int i = 0; i < kTumFields; ++i) {
      if (!ParseDouble(fields[i], &values[i])) {
        throw InputError(Where(path, line_number) + ": not a number: '" + std::string(fields[i]) +
                         "'");
      }
      if (!std::isfinite(values[i])) {
        throw InputError(Where(path, line_number) + ": non-finite value '" +
                         std::string(fields[i]) + "'");
      }
    }
    StampedPose pose;
    pose.timestamp = values[0];
    pose.position = Eigen::Vector3d(values[1], values[2], values[3]);
    // TUM stores qx qy qz qw; Eigen's constructor takes w first.
    pose.rotation = Eigen::Quaterniond(values[7], values[4], values[5], values[6]);
    const double norm = pose.rotation.norm();
    if (!(norm > kMinQuaternionNorm) || !std::isfinite(norm)) {
      throw InputError(Where(path, line_number) + ": quaternion (qx qy qz qw) has zero length");
    }
    pose.rotation.normalize();
    if (!trajectory.empty() && pose.timestamp < trajectory.back().timestamp) {
      throw InputError(Where(path, line_number) + ": timestamp " + std::string(fields[0]) +
                       " is earlier than the previous pose's; timestamps must not decrease");
    }
    trajectory.push_back(pose);
  }
  if (trajectory.empty()) {
    throw InputError(path.string() +
                     ": no poses (expected TUM lines `timestamp tx ty tz qx qy qz qw`)");
  }
  return trajectory;
}

void WriteTumTrajectory(const std::filesystem::path& path, const Trajectory& trajectory) {
  std::string text = "# timestamp tx ty tz qx qy qz qw (world_from_cam, metres, seconds)\n";
  char buffer[512];
  for (const StampedPose& pose : trajectory) {
    const Eigen::Vector3d& p = pose.position;
    const Eigen::Quaterniond& q = pose.rotation;
    // %.17g round-trips any double exactly.
    std::snprintf(buffer, sizeof(buffer), "%.9f %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n",
                  pose.timestamp, p.x(), p.y(), p.z(), q.x(), q.y(), q.z(), q.w());
    text += buffer;
  }
  WriteTextFileAtomically(path, text);
}

StampedPose ToStampedPose(double timestamp, const Eigen::Isometry3d& world_from_cam) {
  StampedPose pose;
  pose.timestamp = timestamp;
  pose.rotation = Eigen::Quaterniond(world_from_cam.linear()).normalized();
  pose.position = world_from_cam.translation();
  return pose;
}

Eigen::Isometry3d ToIsometry(const StampedPose& pose) {
  Eigen::Isometry3d world_from_cam = Eigen::Isometry3d::Identity();
  world_from_cam.linear() = pose.rotation.toRotationMatrix();
  world_from_cam.translation() = pose.position;
  return world_from_cam;
}

}  // namespace pipescope
