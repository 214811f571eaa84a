#include "pipescope/geometry/pipe_cylinder.h"

#include <Eigen/Geometry>
#include <cmath>

namespace pipescope {

std::optional<double> RayToWall(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                                double radius_m) {
  const double a = direction.head<2>().squaredNorm();
  if (a < 1e-12) return std::nullopt;
  const double b = origin.head<2>().dot(direction.head<2>());
  const double c = origin.head<2>().squaredNorm() - radius_m * radius_m;  // < 0 inside
  const double discriminant = b * b - a * c;
  if (discriminant < 0.0) return std::nullopt;
  const double t = (-b + std::sqrt(discriminant)) / a;
  if (t <= 0.0) return std::nullopt;
  return t;
}

PipeAxis StraightCylinderAxis(const double cylinder[4]) {
  const Eigen::Matrix3d rotation = (Eigen::AngleAxisd(cylinder[0], Eigen::Vector3d::UnitX()) *
                                    Eigen::AngleAxisd(cylinder[1], Eigen::Vector3d::UnitY()))
                                       .toRotationMatrix();
  PipeAxis axis;
  axis.point = -rotation.transpose() * Eigen::Vector3d(cylinder[2], cylinder[3], 0.0);
  axis.direction = rotation.transpose() * Eigen::Vector3d::UnitZ();
  return axis;
}

}  // namespace pipescope
