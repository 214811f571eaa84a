#include "pipescope/geometry/tube_section.h"

#include <cmath>

namespace pipescope {

Eigen::Vector3d TubeSection::CentrelinePoint(double s) const {
  const double k = curvature.norm();
  if (k * std::abs(s) < 1e-9) return start + s * axis + 0.5 * s * s * curvature;
  return start + std::sin(k * s) / k * axis + (1.0 - std::cos(k * s)) / (k * k) * curvature;
}

Eigen::Vector3d TubeSection::TangentAt(double s) const {
  const double k = curvature.norm();
  if (k * std::abs(s) < 1e-9) return (axis + s * curvature).normalized();
  return std::cos(k * s) * axis + std::sin(k * s) / k * curvature;
}

Eigen::Vector3d TubeSection::CurvatureAt(double s) const {
  const double k = curvature.norm();
  return std::cos(k * s) * curvature - std::sin(k * s) * k * axis;
}

double TubeSection::ArcCoordinate(const Eigen::Vector3d& point) const {
  const Eigen::Vector3d offset = point - start;
  const double x = offset.dot(axis);
  const double k = curvature.norm();
  if (k < 1e-12) return x;
  // The angle about the bend's centre (start + curvature / k^2) from the start.
  return std::atan2(k * x, 1.0 - offset.dot(curvature)) / k;
}

Eigen::Vector3d SectionJunction(const TubeSection& before, const TubeSection& after) {
  if (before.Curved()) return after.start;
  const Eigen::Vector3d foot = before.start + before.AxialCoordinate(after.start) * before.axis;
  const Eigen::Vector3d fallback = 0.5 * (after.start + foot);
  const double cosine = before.axis.dot(after.axis);
  const double sine_squared = 1.0 - cosine * cosine;
  constexpr double kMinAngleRad = 1.5 * M_PI / 180.0;
  if (sine_squared < std::sin(kMinAngleRad) * std::sin(kMinAngleRad)) return fallback;
  // Closest points of the lines before.start + s a1 and after.start + t a2.
  const Eigen::Vector3d w = before.start - after.start;
  const double d = before.axis.dot(w);
  const double e = after.axis.dot(w);
  const double s = (cosine * e - d) / sine_squared;
  const double t = (e - cosine * d) / sine_squared;
  const Eigen::Vector3d corner =
      0.5 * (before.start + s * before.axis + after.start + t * after.axis);
  if ((corner - after.start).norm() > 3.0 * after.Radius()) return fallback;
  return corner;
}

}  // namespace pipescope
