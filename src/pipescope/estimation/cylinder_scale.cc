#include "pipescope/estimation/cylinder_scale.h"

#include <ceres/ceres.h>

#include <Eigen/Geometry>
#include <cmath>

#include "pipescope/estimation/least_squares_solve.h"
#include "pipescope/util/median.h"

namespace pipescope {
namespace {

// Wall error of a scaled point, e = |P_C (s x)| - r, in the frame of the cylinder C =
// [R_X(gamma) R_Y(beta) | (t_X, t_Y, 0)] of eq. 4 relative to the points' frame (eq. 5-6).
class ScaledWallError {
 public:
  ScaledWallError(const Eigen::Vector3d& point, double radius) : point_(point), radius_(radius) {}

  template <typename T>
  bool operator()(const T* cylinder, const T* scale, T* residual) const {
    const T x0 = scale[0] * point_.x(), y0 = scale[0] * point_.y(), z0 = scale[0] * point_.z();
    const T cb = ceres::cos(cylinder[1]), sb = ceres::sin(cylinder[1]);
    const T cg = ceres::cos(cylinder[0]), sg = ceres::sin(cylinder[0]);
    const T x = cb * x0 + sb * z0 + cylinder[2];
    const T y = cg * y0 - sg * (-sb * x0 + cb * z0) + cylinder[3];
    residual[0] = ceres::sqrt(x * x + y * y + T(1e-18)) - T(radius_);
    return true;
  }

 private:
  Eigen::Vector3d point_;
  double radius_;
};

// The cylinder parameters {gamma, beta, t_X, t_Y} of an axis (inverse of StraightCylinderAxis).
void CylinderFromAxis(const PipeAxis& axis, double cylinder[4]) {
  const Eigen::Vector3d a = axis.direction.normalized();
  // R_X(gamma) R_Y(beta) a = e_Z: R_Y(beta) zeroes a's x component, R_X(gamma) then its y.
  const double beta = std::atan2(-a.x(), a.z());
  const Eigen::Vector3d rotated_y = Eigen::AngleAxisd(beta, Eigen::Vector3d::UnitY()) * a;
  const double gamma = std::atan2(rotated_y.y(), rotated_y.z());
  cylinder[0] = gamma;
  cylinder[1] = beta;
  const Eigen::Matrix3d rotation = (Eigen::AngleAxisd(gamma, Eigen::Vector3d::UnitX()) *
                                    Eigen::AngleAxisd(beta, Eigen::Vector3d::UnitY()))
                                       .toRotationMatrix();
  const Eigen::Vector3d t = -(rotation * axis.point);
  cylinder[2] = t.x();
  cylinder[3] = t.y();
}

}  // namespace

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
  double scale = UpperMedian(ratios);
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

double FitScaleAndAxis(const std::vector<Eigen::Vector3d>& points, double radius, PipeAxis* axis,
                       const CylinderScaleOptions& options) {
  double scale = ScaleFromCylinderRadius(points, *axis, radius, options);
  if (scale <= 0.0) return 0.0;
  double cylinder[4];
  CylinderFromAxis(*axis, cylinder);
  ceres::Problem problem;
  for (const Eigen::Vector3d& point : points) {
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<ScaledWallError, 1, 4, 1>(
                                 new ScaledWallError(point, radius)),
                             new ceres::CauchyLoss(options.cauchy_fraction * radius), cylinder,
                             &scale);
  }
  if (!SolveLeastSquares(&problem, ceres::DENSE_QR, 25, 0).usable || scale <= 0.0) return 0.0;
  *axis = StraightCylinderAxis(cylinder);
  return scale;
}

}  // namespace pipescope
