#include "pipescope/fisheye/cylinder_scale.h"

#include <Eigen/Geometry>
#include <cmath>

#include "pipescope/fisheye/median.h"

namespace pipescope {

PipeAxis StraightCylinderAxis(const double cylinder[4]) {
  const Eigen::Matrix3d rotation = (Eigen::AngleAxisd(cylinder[0], Eigen::Vector3d::UnitX()) *
                                    Eigen::AngleAxisd(cylinder[1], Eigen::Vector3d::UnitY()))
                                       .toRotationMatrix();
  PipeAxis axis;
  axis.point = -rotation.transpose() * Eigen::Vector3d(cylinder[2], cylinder[3], 0.0);
  axis.direction = rotation.transpose() * Eigen::Vector3d::UnitZ();
  return axis;
}

double ScaleFromCylinderRadius(const std::vector<Eigen::Vector3d>& points, const PipeAxis& axis,
                               double radius, const CylinderScaleOptions& options) {
  const Eigen::Vector3d a = axis.direction.normalized();
  const Eigen::Matrix3d perpendicular = Eigen::Matrix3d::Identity() - a * a.transpose();
  const Eigen::Vector3d offset = perpendicular * axis.point;
  std::vector<Eigen::Vector3d> projected;
  std::vector<double> ratios;
  for (const Eigen::Vector3d& x : points) {
    const Eigen::Vector3d p = perpendicular * x;
    if (p.norm() <= 1e-12) continue;
    projected.push_back(p);
    ratios.push_back(radius / p.norm());
  }
  if (projected.empty()) return 0.0;
  double scale = Median(ratios);
  const double cauchy = options.cauchy_fraction * radius;
  for (int iteration = 0; iteration < options.iterations; ++iteration) {
    // e_i(s) = |s p_i - c| - r, de_i/ds = p_i . (s p_i - c) / |s p_i - c|.
    double normal = 0.0, gradient = 0.0;
    for (const Eigen::Vector3d& p : projected) {
      const Eigen::Vector3d from_axis = scale * p - offset;
      const double distance = from_axis.norm();
      if (distance <= 1e-12) continue;
      const double error = distance - radius;
      const double jacobian = p.dot(from_axis) / distance;
      const double weight = 1.0 / (1.0 + (error / cauchy) * (error / cauchy));
      normal += weight * jacobian * jacobian;
      gradient += weight * jacobian * error;
    }
    if (normal <= 0.0) break;
    const double step = gradient / normal;
    scale -= step;
    if (std::abs(step) <= 1e-12 * std::abs(scale)) break;
  }
  return scale;
}

}  // namespace pipescope
