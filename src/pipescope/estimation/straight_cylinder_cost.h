#pragma once

#include <ceres/ceres.h>

namespace pipescope {

// 001 eq. 6 on a straight cylinder relative to the window's first pose (eqs. 4-5), the residual
// of StraightCylinderError (bit for bit) with its Jacobians written out instead of automatic
// differentiation over 14 parameters. Parameters: cylinder {gamma, beta, t_X, t_Y}, the first
// pose's quaternion (w, x, y, z) and translation, and the point.
//
// A second residual, always zero, pads the term to two rows like the reprojection errors: with
// every residual of a point two rows long, Ceres' Schur elimination of the points takes its
// fixed-size <2, 3, dynamic> kernels instead of the all-dynamic one. The cost is unchanged.
class StraightCylinderCost : public ceres::SizedCostFunction<2, 4, 4, 3, 3> {
 public:
  StraightCylinderCost(double radius, double tau);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  double radius_;
  double sqrt_tau_;
};

}  // namespace pipescope
