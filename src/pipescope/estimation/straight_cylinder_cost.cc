#include "pipescope/estimation/straight_cylinder_cost.h"

#include <ceres/rotation.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "pipescope/geometry/quaternion_rotation_jacobian.h"

namespace pipescope {

StraightCylinderCost::StraightCylinderCost(double radius, double tau)
    : radius_(radius), sqrt_tau_(std::sqrt(tau)) {}

bool StraightCylinderCost::Evaluate(double const* const* parameters, double* residuals,
                                    double** jacobians) const {
  const double* cylinder = parameters[0];
  const double* rotation = parameters[1];
  const double* translation = parameters[2];
  const double* point_world = parameters[3];
  // Eq. 5 as StraightCylinderError writes it: X_m = R_m X + t_m, then R_Y(beta), R_X(gamma), t~.
  double p[3];
  ceres::QuaternionRotatePoint(rotation, point_world, p);
  for (int k = 0; k < 3; ++k) p[k] += translation[k];
  const double cb = std::cos(cylinder[1]), sb = std::sin(cylinder[1]);
  const double cg = std::cos(cylinder[0]), sg = std::sin(cylinder[0]);
  const double x1 = cb * p[0] + sb * p[2];
  const double y1 = p[1];
  const double z1 = -sb * p[0] + cb * p[2];
  const double x = x1 + cylinder[2];
  const double y = cg * y1 - sg * z1 + cylinder[3];
  const double rho = std::sqrt(x * x + y * y + 1e-18);
  residuals[0] = sqrt_tau_ * (rho - radius_);  // eq. 6, times sqrt(tau)
  residuals[1] = 0.0;                          // the padding row
  if (!jacobians) return true;
  const int sizes[4] = {4, 4, 3, 3};
  for (int block = 0; block < 4; ++block) {
    if (jacobians[block]) std::fill_n(jacobians[block] + sizes[block], sizes[block], 0.0);
  }
  const double de_dx = sqrt_tau_ * x / rho;
  const double de_dy = sqrt_tau_ * y / rho;
  if (jacobians[0]) {
    // dy/dgamma = -sg y1 - cg z1; dx/dbeta = z1, dy/dbeta = sg x1 (dz1/dbeta = -x1).
    jacobians[0][0] = de_dy * (-sg * y1 - cg * z1);
    jacobians[0][1] = de_dx * z1 + de_dy * sg * x1;
    jacobians[0][2] = de_dx;
    jacobians[0][3] = de_dy;
  }
  // d e / d X_m: dx/dX_m = (cb, 0, sb), dy/dX_m = (sg sb, cg, -sg cb).
  const Eigen::RowVector3d de_dp(de_dx * cb + de_dy * sg * sb, de_dy * cg,
                                 de_dx * sb - de_dy * sg * cb);
  if (jacobians[1]) {
    Eigen::Map<Eigen::RowVector4d> out(jacobians[1]);
    out = de_dp * QuaternionRotatePointJacobian(rotation, point_world);
  }
  if (jacobians[2]) Eigen::Map<Eigen::RowVector3d>{jacobians[2]} = de_dp;
  if (jacobians[3]) {
    Eigen::Map<Eigen::RowVector3d> out(jacobians[3]);
    out = de_dp * QuaternionRotationMatrix(rotation);
  }
  return true;
}

}  // namespace pipescope
