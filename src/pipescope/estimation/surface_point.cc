#include "pipescope/estimation/surface_point.h"

#include <cmath>

#include "pipescope/geometry/pipe_cylinder.h"

namespace pipescope {

std::optional<Eigen::Vector3d> WallPointOfBearing(const Eigen::Isometry3d& world_from_cam,
                                                  const Eigen::Vector3d& bearing_cam,
                                                  double radius_m) {
  const Eigen::Vector3d origin = world_from_cam.translation();
  const Eigen::Vector3d direction = world_from_cam.linear() * bearing_cam;
  // Eq. 37 is RayToWall's quadratic with kappa = t |bearing|.
  const std::optional<double> t = RayToWall(origin, direction, radius_m);
  if (!t) return std::nullopt;
  return origin + *t * direction;
}

SurfacePoint ToSurface(const Eigen::Vector3d& point_world, double radius_m,
                       double phi_reference_rad) {
  double phi = std::atan2(point_world.y(), point_world.x()) - phi_reference_rad;
  phi = std::remainder(phi, 2.0 * M_PI);
  return {point_world.z(), radius_m * phi};
}

Eigen::Vector3d FromSurface(const SurfacePoint& point, double radius_m, double phi_reference_rad) {
  const double phi = point.rho / radius_m + phi_reference_rad;
  return {radius_m * std::cos(phi), radius_m * std::sin(phi), point.h};
}

}  // namespace pipescope
