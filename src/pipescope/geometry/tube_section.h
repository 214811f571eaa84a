#pragma once

#include <Eigen/Core>
#include <cmath>

namespace pipescope {

// One straight cylindrical section of a tube (004 eq. 3): a point on its axis where the section
// starts, the axis' unit direction and the log of the radius. Bends are chains of sections.
struct TubeSection {
  Eigen::Vector3d start = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  double log_radius = 0.0;

  double Radius() const { return std::exp(log_radius); }
  // Signed distance of `point` along the axis from `start`.
  double AxialCoordinate(const Eigen::Vector3d& point) const { return (point - start).dot(axis); }
  // Distance of `point` from the axis line.
  double DistanceFromAxis(const Eigen::Vector3d& point) const {
    const Eigen::Vector3d offset = point - start;
    return (offset - offset.dot(axis) * axis).norm();
  }
};

// Where consecutive sections of a chain meet: the point where their axes pass closest (the
// corner of the chain, so the junction follows the axes as they are estimated), or, for axes
// within a degree and a half of each other or a corner more than three radii from the second
// section's start, halfway between that start and its foot on the first axis.
Eigen::Vector3d SectionJunction(const TubeSection& before, const TubeSection& after);

// 004 eq. 8 for a cylinder: the distance alpha > 0 along the ray origin + alpha * direction at
// which a ray from inside the cylinder (axis through `axis_point` along the unit `axis`, radius
// `radius`) meets its wall. With o, d the parts of (origin - axis_point) and direction across the
// axis, |o + alpha d|^2 = radius^2 has the positive root
//   alpha = (-o.d + sqrt((o.d)^2 - |d|^2 (|o|^2 - radius^2))) / |d|^2.
// Returns false for a ray along the axis, or an origin outside the cylinder. Templated so that
// ceres::Jet differentiates it for the filter's Jacobians.
template <typename T>
bool IntersectRayWithCylinder(const Eigen::Matrix<T, 3, 1>& origin,
                              const Eigen::Matrix<T, 3, 1>& direction,
                              const Eigen::Matrix<T, 3, 1>& axis_point,
                              const Eigen::Matrix<T, 3, 1>& axis, const T& radius, T* alpha) {
  using std::sqrt;
  const Eigen::Matrix<T, 3, 1> offset = origin - axis_point;
  const Eigen::Matrix<T, 3, 1> o = offset - offset.dot(axis) * axis;
  const Eigen::Matrix<T, 3, 1> d = direction - direction.dot(axis) * axis;
  const T dd = d.squaredNorm();
  if (!(dd > T(1e-12) * direction.squaredNorm())) return false;
  const T od = o.dot(d);
  const T inside = radius * radius - o.squaredNorm();
  if (!(inside > T(0))) return false;
  *alpha = (-od + sqrt(od * od + dd * inside)) / dd;
  return true;
}

}  // namespace pipescope
