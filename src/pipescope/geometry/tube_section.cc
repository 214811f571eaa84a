#include "pipescope/geometry/tube_section.h"

namespace pipescope {

Eigen::Vector3d SectionJunction(const TubeSection& before, const TubeSection& after) {
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
