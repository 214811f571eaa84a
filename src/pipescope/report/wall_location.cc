#include "pipescope/report/wall_location.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "pipescope/geometry/clock_position.h"
#include "pipescope/geometry/pipe_cylinder.h"

namespace pipescope {

std::optional<WallLocation> LocateOnCylinder(const Camera& camera,
                                             const Eigen::Isometry3d& world_from_cam,
                                             const Station& station, const Eigen::Vector2d& pixel,
                                             double radius_m, const PipeAxis& axis,
                                             const Eigen::Vector3d& up) {
  Eigen::Vector3d bearing;
  if (!camera.Unproject(pixel, &bearing)) return std::nullopt;
  const Eigen::Vector3d origin = world_from_cam.translation();
  const Eigen::Vector3d direction = (world_from_cam.linear() * bearing).normalized();
  // In a frame whose Z axis is the cylinder's axis, RayToWall meets |xy| = radius.
  const Eigen::Vector3d along = axis.direction.normalized();
  const Eigen::Matrix3d axis_from_world =
      Eigen::Quaterniond::FromTwoVectors(along, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d origin_in_axis = axis_from_world * (origin - axis.point);
  if (origin_in_axis.head<2>().norm() >= radius_m) return std::nullopt;
  const std::optional<double> t = RayToWall(origin_in_axis, axis_from_world * direction, radius_m);
  if (!t) return std::nullopt;
  // Along the pipe is along its axis, pointed the way of the survey: the path's own direction
  // may lean on the axis, and would then add part of the radius to the distance.
  const Eigen::Vector3d survey = along.dot(station.travel) < 0.0 ? Eigen::Vector3d(-along) : along;
  WallLocation location;
  location.point = origin + *t * direction;
  location.distance_m = station.distance_m + (location.point - origin).dot(survey);
  const Eigen::Vector3d from_axis = location.point - axis.point;
  const Eigen::Vector3d radial = from_axis - from_axis.dot(along) * along;
  const std::optional<double> clock = ClockAngleDeg(radial, survey, up);
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
