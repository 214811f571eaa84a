#include "pipescope/report/wall_location.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "pipescope/geometry/clock_position.h"
#include "pipescope/geometry/pipe_cylinder.h"

namespace pipescope {

std::optional<WallLocation> LocateOnStraightPipe(const Camera& camera,
                                                 const Eigen::Isometry3d& world_from_cam,
                                                 const Station& station,
                                                 const Eigen::Vector2d& pixel, double radius_m,
                                                 const Eigen::Vector3d& up) {
  Eigen::Vector3d bearing;
  if (!camera.Unproject(pixel, &bearing)) return std::nullopt;
  const Eigen::Vector3d origin = world_from_cam.translation();
  const Eigen::Vector3d direction = (world_from_cam.linear() * bearing).normalized();
  const std::optional<double> t = RayToWall(origin, direction, radius_m);
  if (!t) return std::nullopt;
  WallLocation location;
  location.point = origin + *t * direction;
  location.distance_m = station.distance_m + (location.point - origin).dot(station.travel);
  const Eigen::Vector3d radial(location.point.x(), location.point.y(), 0.0);
  const std::optional<double> clock = ClockAngleDeg(radial, station.travel, up);
  location.clock_angle_deg = clock.value_or(std::numeric_limits<double>::quiet_NaN());
  if (clock) location.clock = ClockString(*clock);
  return location;
}

std::pair<double, double> ClockSpan(const std::vector<double>& angles_deg) {
  std::vector<double> angles;
  for (double angle : angles_deg) {
    if (!std::isfinite(angle)) continue;
    angle = std::fmod(angle, 360.0);
    angles.push_back(angle < 0.0 ? angle + 360.0 : angle);
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (angles.empty()) return {nan, nan};
  std::sort(angles.begin(), angles.end());
  // The arc is the circle less its largest gap between neighbouring angles.
  std::size_t after_gap = 0;
  double largest_gap = angles.front() + 360.0 - angles.back();
  for (std::size_t i = 1; i < angles.size(); ++i) {
    if (angles[i] - angles[i - 1] > largest_gap) {
      largest_gap = angles[i] - angles[i - 1];
      after_gap = i;
    }
  }
  const double from = angles[after_gap];
  const double to = angles[after_gap == 0 ? angles.size() - 1 : after_gap - 1];
  return {from, to};
}

}  // namespace pipescope
