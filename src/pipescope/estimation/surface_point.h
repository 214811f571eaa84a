#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>

namespace pipescope {

// A point on the wall of a straight pipe of radius r whose axis is the world Z axis, in the
// surface coordinates of 000 §5.3.1: h along the axis and rho = r phi around it. phi is measured
// from `phi_reference_rad` and wrapped to (-pi, pi], so a camera looking at the wall near the
// reference never sees the wrap (000 footnote 9's "constant global offset").
struct SurfacePoint {
  double h = 0.0;
  double rho = 0.0;
};

// The scene-point constraint of 000 §5.2 (eq. 35-39): the ray of `bearing_cam` (camera frame)
// from the camera at `world_from_cam` meets the wall where the positive root kappa of eq. 37
// puts it (geometry/RayToWall). Unset when the ray runs along the axis or the camera is outside
// the pipe.
std::optional<Eigen::Vector3d> WallPointOfBearing(const Eigen::Isometry3d& world_from_cam,
                                                  const Eigen::Vector3d& bearing_cam,
                                                  double radius_m);

// (h, rho) of a world point (eq. 1), rho = radius_m * (phi - phi_reference_rad) wrapped.
SurfacePoint ToSurface(const Eigen::Vector3d& point_world, double radius_m,
                       double phi_reference_rad);

// The world point of (h, rho), the inverse of ToSurface on the wall.
Eigen::Vector3d FromSurface(const SurfacePoint& point, double radius_m, double phi_reference_rad);

}  // namespace pipescope
