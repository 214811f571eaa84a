#pragma once

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/Core>

namespace pipescope {

// Prior tying a window's straight cylinder (001 eq. 4, relative to the window's first pose) to
// the axis of the previous window in the same straight section. The pipe is one straight
// cylinder, so window k's axis, expressed in the world, continues window k-1's; without the
// prior each window fits a free local cylinder from its fixed first pose, and the heading that
// pose inherits drifts on from window to window.
//
// With the prior the first pose's rotation R_m is free (its translation stays the gauge), so
// the window can turn back the heading it inherited. The previous axis, a unit direction a_w
// and a point p_w in the world, is brought into the first camera's frame, a_p = R_m a_w and
// p_p = R_m p_w + t_m. The cylinder's axis in that frame (StraightCylinderAxis) has direction
// a = R~^T e_Z and point c = -R~^T t~. The residuals are
//
//   (a x a_p) / sigma_direction                      (sine of the angle between the axes)
//   (c - (c.a) a - (p_p - (p_p.a_p) a_p)) / sigma_position
//                                   (the lines' points nearest the first camera: their offset)
//   2 vec(q_m q_0^-1) / sigma_rotation               (R_m's turn from its start R_0)
//
// The last holds the roll about the pipe axis, which the cylinder does not fix. One sigma of
// each counts as a pixel of reprojection error (eq. 2's image term).
class CylinderAxisPriorError {
 public:
  CylinderAxisPriorError(const Eigen::Vector3d& previous_direction_world,
                         const Eigen::Vector3d& previous_point_world,
                         const double start_rotation[4], double sigma_direction_rad,
                         double sigma_position_m, double sigma_rotation_rad)
      : direction_(previous_direction_world.normalized()),
        point_(previous_point_world),
        inv_sigma_direction_(1.0 / sigma_direction_rad),
        inv_sigma_position_(1.0 / sigma_position_m),
        inv_sigma_rotation_(1.0 / sigma_rotation_rad) {
    for (int k = 0; k < 4; ++k) start_rotation_[k] = start_rotation[k];
  }

  template <typename T>
  bool operator()(const T* cylinder, const T* first_rotation, const T* first_translation,
                  T* residual) const {
    const T cb = ceres::cos(cylinder[1]), sb = ceres::sin(cylinder[1]);
    const T cg = ceres::cos(cylinder[0]), sg = ceres::sin(cylinder[0]);
    // R~ = R_X(gamma) R_Y(beta); a = R~^T e_Z is R~'s third row, c = -R~^T (t_X, t_Y, 0).
    const T a[3] = {-sb * cg, sg, cb * cg};
    const T c[3] = {-(cb * cylinder[2] + sb * sg * cylinder[3]), -cg * cylinder[3],
                    -(sb * cylinder[2] - sg * cb * cylinder[3])};
    const T direction_world[3] = {T(direction_.x()), T(direction_.y()), T(direction_.z())};
    const T point_world[3] = {T(point_.x()), T(point_.y()), T(point_.z())};
    T ap[3], pp[3];
    ceres::QuaternionRotatePoint(first_rotation, direction_world, ap);
    ceres::QuaternionRotatePoint(first_rotation, point_world, pp);
    for (int k = 0; k < 3; ++k) pp[k] += first_translation[k];
    residual[0] = T(inv_sigma_direction_) * (a[1] * ap[2] - a[2] * ap[1]);
    residual[1] = T(inv_sigma_direction_) * (a[2] * ap[0] - a[0] * ap[2]);
    residual[2] = T(inv_sigma_direction_) * (a[0] * ap[1] - a[1] * ap[0]);
    const T c_along = c[0] * a[0] + c[1] * a[1] + c[2] * a[2];
    const T p_along = pp[0] * ap[0] + pp[1] * ap[1] + pp[2] * ap[2];
    for (int k = 0; k < 3; ++k) {
      residual[3 + k] =
          T(inv_sigma_position_) * ((c[k] - c_along * a[k]) - (pp[k] - p_along * ap[k]));
    }
    // q_m q_0^-1 (unit quaternions, w first): its vector part is sin(angle / 2) times the axis.
    const T start_inverse[4] = {T(start_rotation_[0]), T(-start_rotation_[1]),
                                T(-start_rotation_[2]), T(-start_rotation_[3])};
    T turn[4];
    ceres::QuaternionProduct(first_rotation, start_inverse, turn);
    const T sign = turn[0] < T(0) ? T(-1) : T(1);
    for (int k = 0; k < 3; ++k) residual[6 + k] = T(2.0 * inv_sigma_rotation_) * sign * turn[1 + k];
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Vector3d& previous_direction_world,
                                     const Eigen::Vector3d& previous_point_world,
                                     const double start_rotation[4], double sigma_direction_rad,
                                     double sigma_position_m, double sigma_rotation_rad) {
    return new ceres::AutoDiffCostFunction<CylinderAxisPriorError, 9, 4, 4, 3>(
        new CylinderAxisPriorError(previous_direction_world, previous_point_world, start_rotation,
                                   sigma_direction_rad, sigma_position_m, sigma_rotation_rad));
  }

 private:
  Eigen::Vector3d direction_;  // the previous axis in the world
  Eigen::Vector3d point_;
  double start_rotation_[4];  // the first pose's rotation before the adjustment
  double inv_sigma_direction_;
  double inv_sigma_position_;
  double inv_sigma_rotation_;
};

}  // namespace pipescope
