#pragma once

#include <ceres/ceres.h>

#include <Eigen/Core>
#include <vector>

#include "pipescope/camera/camera_models.h"

namespace pipescope {

// 001 eq. 3, r = u - pi(R_cw X + t_cw), with its Jacobians written out instead of automatic
// differentiation over all ten parameters (FisheyeReprojectionError, which gives the same
// residual): the rotation's and the point's derivatives are closed forms, and only the camera
// model's 2x3 derivative d pi / d X_cam goes through ceres::Jet, over 3 variables instead of 10.
// The quaternion (w, x, y, z) need not be unit (normalised as ceres::QuaternionRotatePoint does).
//
// Residual r (2) and, when non-null, the Jacobians d r / d q (2x4), d r / d t (2x3) and
// d r / d X (2x3), row-major. Returns false where the model cannot project.
bool EvaluateFisheyeReprojection(CameraModelId model_id, const double* params,
                                 const Eigen::Vector2d& observed, const double* rotation,
                                 const double* translation, const double* point_world,
                                 double* residual, double* d_rotation, double* d_translation,
                                 double* d_point);

// Parameters: quaternion (4), translation (3), point (3).
class FisheyeReprojectionCost : public ceres::SizedCostFunction<2, 4, 3, 3> {
 public:
  FisheyeReprojectionCost(CameraModelId model_id, const std::vector<double>& params,
                          const Eigen::Vector2d& observed);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  CameraModelId model_id_;
  double params_[kMaxNumCameraParams];
  Eigen::Vector2d observed_;
};

// Parameters: one pose block, quaternion then translation (7), and the point (3).
class FisheyePoseBlockReprojectionCost : public ceres::SizedCostFunction<2, 7, 3> {
 public:
  FisheyePoseBlockReprojectionCost(CameraModelId model_id, const std::vector<double>& params,
                                   const Eigen::Vector2d& observed);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  CameraModelId model_id_;
  double params_[kMaxNumCameraParams];
  Eigen::Vector2d observed_;
};

}  // namespace pipescope
