#pragma once

#include <Eigen/Core>

namespace pipescope {

// d (R(q) X) / d q for ceres::QuaternionRotatePoint(q, X) (quaternion w, x, y, z, normalised
// there, so q need not be unit). With u = q / |q| = (w, v):
//
//   R(u) X = X + 2 w (v x X) + 2 v x (v x X),
//   d/dw = 2 v x X,   d/dv = -2 w [X]x + 2 (v X^T + (v.X) I - 2 X v^T),
//
// times d u / d q = (I - u u^T) / |q|.
inline Eigen::Matrix<double, 3, 4> QuaternionRotatePointJacobian(const double* q_data,
                                                                 const double* x_data) {
  const Eigen::Map<const Eigen::Vector4d> q(q_data);
  const Eigen::Map<const Eigen::Vector3d> x(x_data);
  const double inverse_norm = 1.0 / q.norm();
  const Eigen::Vector4d unit = inverse_norm * q;
  const double w = unit(0);
  const Eigen::Vector3d v = unit.tail<3>();
  Eigen::Matrix<double, 3, 4> d_unit;
  d_unit.col(0) = 2.0 * v.cross(x);
  Eigen::Matrix3d skew_x;
  skew_x << 0, -x.z(), x.y(), x.z(), 0, -x.x(), -x.y(), x.x(), 0;
  d_unit.rightCols<3>() =
      -2.0 * w * skew_x +
      2.0 * (v * x.transpose() + v.dot(x) * Eigen::Matrix3d::Identity() - 2.0 * x * v.transpose());
  return d_unit * (inverse_norm * (Eigen::Matrix4d::Identity() - unit * unit.transpose()));
}

// R(q / |q|) as a matrix.
inline Eigen::Matrix3d QuaternionRotationMatrix(const double* q_data) {
  const Eigen::Vector4d u = Eigen::Map<const Eigen::Vector4d>(q_data).normalized();
  const double w = u(0), x = u(1), y = u(2), z = u(3);
  Eigen::Matrix3d r;
  r << 1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),  //
      2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),   //
      2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y);
  return r;
}

}  // namespace pipescope
