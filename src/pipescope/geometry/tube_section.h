#pragma once

#include <Eigen/Core>
#include <cmath>
#include <type_traits>

namespace pipescope {

// One section of a tube (004 eq. 3): a point on its centreline where the section starts, the
// centreline's unit direction there (the axis) and the log of the radius. Beyond 004 a section
// may bend: `curvature` (1/m, across the axis, towards the bend's centre) makes it a torus
// segment, its centreline the circular arc that leaves `start` along `axis`; zero is 004's
// straight cylinder. A chain of straight sections only approximates a bend, and its misfit pulls
// the estimated turn short (docs/ekf.md).
struct TubeSection {
  Eigen::Vector3d start = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  double log_radius = 0.0;
  Eigen::Vector3d curvature = Eigen::Vector3d::Zero();

  double Radius() const { return std::exp(log_radius); }
  bool Curved() const { return curvature.squaredNorm() > 0.0; }
  // The centreline at arc length `s` from the start, its unit tangent there, and the arc length
  // of `point`'s foot on it (the angle about the bend's centre times its radius; for a straight
  // section, AxialCoordinate).
  Eigen::Vector3d CentrelinePoint(double s) const;
  Eigen::Vector3d TangentAt(double s) const;
  double ArcCoordinate(const Eigen::Vector3d& point) const;
  // The curvature vector at arc length `s` (it turns with the tangent).
  Eigen::Vector3d CurvatureAt(double s) const;
  // Signed distance of `point` along the axis from `start`.
  double AxialCoordinate(const Eigen::Vector3d& point) const { return (point - start).dot(axis); }
  // Distance of `point` from the axis line.
  double DistanceFromAxis(const Eigen::Vector3d& point) const {
    const Eigen::Vector3d offset = point - start;
    return (offset - offset.dot(axis) * axis).norm();
  }
};

// Where consecutive sections of a chain meet. After a bending section: the next one's start (a
// bending chain is started tangent at the end of the arc). Otherwise the point where their axes
// pass closest (the corner of the chain, so the junction follows the axes as they are estimated),
// or, for axes within a degree and a half of each other or a corner more than three radii from the
// second section's start, halfway between that start and its foot on the first axis.
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

// The squared distance of a point from a section's centreline (the circle of the arc, or the
// axis line): with w = point - start, x = w.axis, u = w.curvature,
//   d^2 = |w|^2 - 2 x^2 / (sqrt(|curvature|^2 x^2 + (1 - u)^2) + 1 - u),
// the circle's distance rewritten so that it has no 1/|curvature| and tends to the axis line's
// |w|^2 - x^2 as the curvature vanishes (what a Jet needs near a straight section).
template <typename T>
T SquaredDistanceFromCentreline(const Eigen::Matrix<T, 3, 1>& offset,
                                const Eigen::Matrix<T, 3, 1>& axis,
                                const Eigen::Matrix<T, 3, 1>& curvature) {
  using std::sqrt;
  const T x = offset.dot(axis);
  const T one_minus_u = T(1) - offset.dot(curvature);
  return offset.squaredNorm() -
         T(2) * x * x /
             (sqrt(curvature.squaredNorm() * x * x + one_minus_u * one_minus_u) + one_minus_u);
}

inline double ScalarValue(double value) { return value; }
template <typename T>
double ScalarValue(const T& jet) {
  return jet.a;
}

// 004 eq. 8 for a bending section (a torus segment): the distance alpha > 0 along the ray at
// which it meets the wall, SquaredDistanceFromCentreline(origin + alpha direction - start) =
// radius^2, by Newton's method from the cylinder along the arc's tangent at the origin's foot.
// `curvature` is taken across `axis` (its part along it dropped). False when the ray meets no
// wall ahead.
template <typename T>
bool IntersectRayWithTubeSection(const Eigen::Matrix<T, 3, 1>& origin,
                                 const Eigen::Matrix<T, 3, 1>& direction,
                                 const Eigen::Matrix<T, 3, 1>& start,
                                 const Eigen::Matrix<T, 3, 1>& axis,
                                 const Eigen::Matrix<T, 3, 1>& curvature, const T& radius,
                                 T* alpha) {
  const Eigen::Matrix<T, 3, 1> across = curvature - curvature.dot(axis) * axis;
  // The values, once: Newton's method runs in doubles.
  Eigen::Vector3d o, d, s, x, k;
  for (int i = 0; i < 3; ++i) {
    o[i] = ScalarValue(origin[i]);
    d[i] = ScalarValue(direction[i]);
    s[i] = ScalarValue(start[i]);
    x[i] = ScalarValue(axis[i]);
    k[i] = ScalarValue(across[i]);
  }
  const double r = ScalarValue(radius);
  if (k.squaredNorm() == 0.0) {
    // A straight section's root is exact; a Jet still iterates, for its curvature derivatives.
    if (!IntersectRayWithCylinder<T>(origin, direction, start, axis, radius, alpha)) return false;
    if (std::is_same_v<T, double>) return true;
  } else {
    // The first guess: the cylinder along the arc's tangent at the origin's foot (far along a
    // bend the start's own axis has left the tube).
    TubeSection local;
    local.start = s;
    local.axis = x;
    local.curvature = k;
    const double foot = local.ArcCoordinate(o);
    double guess = 0.0;
    if (!IntersectRayWithCylinder<double>(o, d, local.CentrelinePoint(foot), local.TangentAt(foot),
                                          r, &guess)) {
      return false;
    }
    *alpha = T(guess);
  }
  auto value = [&](double a) {
    return SquaredDistanceFromCentreline<double>(o + a * d - s, x, k) - r * r;
  };
  // Newton's method in doubles; then one step with T from the root, which leaves its value and
  // gives a Jet the implicit derivative, d alpha = -dF / (dF/d alpha).
  const double h = 1e-6 * r;
  double a = ScalarValue(*alpha), slope = 0.0;
  bool converged = false;
  for (int iteration = 0; iteration < 12 && !converged; ++iteration) {
    slope = (value(a + h) - value(a - h)) / (2.0 * h);
    if (!(slope > 0.0)) return false;  // leaving the wall, or tangent to it
    const double step = value(a) / slope;
    a -= step;
    converged = std::abs(step) < 1e-12 * r;
  }
  if (!converged || !(a > 0.0)) return false;
  const T residual =
      SquaredDistanceFromCentreline<T>(origin + T(a) * direction - start, axis, across) -
      radius * radius;
  *alpha = T(a) - residual / slope;
  return true;
}

}  // namespace pipescope
