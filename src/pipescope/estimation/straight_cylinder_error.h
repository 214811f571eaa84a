#pragma once

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <cmath>

namespace pipescope {

// Scene point error against a straight cylinder of known radius, 001 eqs. 4-6.
//
// The cylinder C has 4 degrees of freedom and is defined relative to the window's first camera
// pose P_m = [R_m | t_m] (cam_from_world) as the origin (eq. 4):
//
//   C = [R~ | t~] = [R_X(gamma) R_Y(beta) | (t_X, t_Y, 0)^T].
//
// A world point X maps into the cylinder frame by (eq. 5)
//
//   X~ = R~ (R_m X + t_m) + t~,
//
// whose Z axis is the cylinder axis, so the point's distance from the wall is (eq. 6)
//
//   e = sqrt(X~^2 + Y~^2) - r.
//
// The residual is sqrt(tau) e, so that its square summed over the points is tau epsilon_X of
// eq. 2 (tau = 2.5e5 in 001). Rotations about Z and translations along Z leave e unchanged, which
// is why 4 parameters suffice. Parameters: cylinder {gamma, beta, t_X, t_Y}, P_m's quaternion
// (w, x, y, z) and translation, and the point.
class StraightCylinderError {
 public:
  StraightCylinderError(double radius, double tau) : radius_(radius), sqrt_tau_(std::sqrt(tau)) {}

  template <typename T>
  bool operator()(const T* cylinder, const T* first_rotation, const T* first_translation,
                  const T* point_world, T* residual) const {
    T point_first[3];
    ceres::QuaternionRotatePoint(first_rotation, point_world, point_first);
    for (int k = 0; k < 3; ++k) point_first[k] += first_translation[k];
    // R_Y(beta) first, then R_X(gamma).
    const T cb = ceres::cos(cylinder[1]), sb = ceres::sin(cylinder[1]);
    const T cg = ceres::cos(cylinder[0]), sg = ceres::sin(cylinder[0]);
    const T x1 = cb * point_first[0] + sb * point_first[2];
    const T y1 = point_first[1];
    const T z1 = -sb * point_first[0] + cb * point_first[2];
    const T x = x1 + cylinder[2];
    const T y = cg * y1 - sg * z1 + cylinder[3];
    residual[0] = T(sqrt_tau_) * (ceres::sqrt(x * x + y * y + T(1e-18)) - T(radius_));
    return true;
  }

  static ceres::CostFunction* Create(double radius, double tau) {
    return new ceres::AutoDiffCostFunction<StraightCylinderError, 1, 4, 4, 3, 3>(
        new StraightCylinderError(radius, tau));
  }

 private:
  double radius_;
  double sqrt_tau_;
};

}  // namespace pipescope
