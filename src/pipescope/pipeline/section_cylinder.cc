#include "pipescope/pipeline/section_cylinder.h"

#include <algorithm>
#include <cmath>

#include "pipescope/estimation/straight_window_adjustment.h"
#include "pipescope/util/median.h"

namespace pipescope {

std::optional<SectionCylinderFit> FitSectionCylinder(const std::vector<SparsePoint>& points,
                                                     int section,
                                                     const Eigen::Isometry3d& world_from_origin,
                                                     const Eigen::Vector3d& far_centre,
                                                     double radius_m, double slack_m) {
  const Eigen::Vector3d origin_centre = world_from_origin.translation();
  const Eigen::Vector3d away = far_centre - origin_centre;
  const double length = away.norm();
  if (length <= 0.0) return std::nullopt;
  StraightWindow window;
  window.poses.push_back(WindowPose::FromIsometry(world_from_origin.inverse()));
  for (const SparsePoint& point : points) {
    if (point.section != section) continue;
    const double s = (point.position - origin_centre).dot(away) / length;
    if (s < 0.0 || s > length + slack_m) continue;
    window.points.push_back(point.position);
  }
  if (window.points.size() < 20) return std::nullopt;
  StraightWindowOptions options;
  options.radius_m = radius_m;
  FitStraightCylinder(options, &window);
  SectionCylinderFit fit;
  std::copy(window.cylinder, window.cylinder + 4, fit.cylinder);
  fit.points = static_cast<int>(window.points.size());
  const PipeAxis axis = StraightCylinderAxis(fit.cylinder);
  const Eigen::Isometry3d cam_from_world = world_from_origin.inverse();
  std::vector<double> distances;
  for (const Eigen::Vector3d& point : window.points) {
    const Eigen::Vector3d v = cam_from_world * point - axis.point;
    distances.push_back(std::abs((v - v.dot(axis.direction) * axis.direction).norm() - radius_m));
  }
  fit.median_distance_m = UpperMedian(distances);
  return fit;
}

PipeAxis SectionCylinderAxis(const SectionCylinderFit& fit,
                             const Eigen::Isometry3d& world_from_origin,
                             const Eigen::Vector3d& far_centre) {
  const PipeAxis in_camera = StraightCylinderAxis(fit.cylinder);
  PipeAxis axis{world_from_origin * in_camera.point,
                (world_from_origin.linear() * in_camera.direction).normalized()};
  if (axis.direction.dot(far_centre - world_from_origin.translation()) < 0.0) {
    axis.direction = -axis.direction;
  }
  return axis;
}

}  // namespace pipescope
