#include "pipescope/geometry/clock_position.h"

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>

namespace pipescope {
namespace {

// Below this share of its length across the pipe, a vector has no usable direction there.
constexpr double kMinAcross = 1e-6;

Eigen::Vector3d AcrossPipe(const Eigen::Vector3d& v, const Eigen::Vector3d& travel) {
  return v - v.dot(travel) * travel;
}

}  // namespace

std::optional<double> ClockAngleDeg(const Eigen::Vector3d& radial, const Eigen::Vector3d& travel,
                                    const Eigen::Vector3d& up) {
  const Eigen::Vector3d top = AcrossPipe(up, travel);
  const Eigen::Vector3d towards = AcrossPipe(radial, travel);
  if (top.norm() < kMinAcross * up.norm() || towards.norm() < kMinAcross * radial.norm()) {
    return std::nullopt;
  }
  // Looking along `travel` with `top` up, the right-hand side is travel x top (the OpenCV camera:
  // z forward, -y up, x right = z x -y).
  const Eigen::Vector3d right = travel.cross(top);
  double angle =
      std::atan2(towards.dot(right.normalized()), towards.dot(top.normalized())) * 180.0 / M_PI;
  if (angle < 0.0) angle += 360.0;
  return angle >= 360.0 ? 0.0 : angle;
}

std::string ClockString(double angle_deg) {
  double wrapped = std::fmod(angle_deg, 360.0);
  if (wrapped < 0.0) wrapped += 360.0;
  // 720 minutes of the clock to a turn.
  const long minutes = std::lround(wrapped * 2.0) % 720;
  long hours = minutes / 60;
  if (hours == 0) hours = 12;
  char text[16];
  std::snprintf(text, sizeof(text), "%ld:%02ld", hours, minutes % 60);
  return text;
}

Eigen::Vector3d CameraUpright(const Eigen::Matrix3d& world_from_cam_rotation) {
  return -world_from_cam_rotation.col(1);
}

}  // namespace pipescope
