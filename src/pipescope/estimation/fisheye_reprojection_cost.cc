#include "pipescope/estimation/fisheye_reprojection_cost.h"

#include <ceres/jet.h>
#include <ceres/rotation.h>

#include <cmath>

#include "pipescope/geometry/quaternion_rotation_jacobian.h"

namespace pipescope {
namespace {

using RowMajor2x3 = Eigen::Matrix<double, 2, 3, Eigen::RowMajor>;
using RowMajor2x3Map = Eigen::Map<RowMajor2x3>;

void CopyParams(const std::vector<double>& params, double* out) {
  for (int k = 0; k < kMaxNumCameraParams; ++k) {
    out[k] = k < static_cast<int>(params.size()) ? params[k] : 0.0;
  }
}

}  // namespace

bool EvaluateFisheyeReprojection(CameraModelId model_id, const double* params,
                                 const Eigen::Vector2d& observed, const double* rotation,
                                 const double* translation, const double* point_world,
                                 double* residual, double* d_rotation, double* d_translation,
                                 double* d_point) {
  // X_cam = R X + t, computed as FisheyeReprojectionError computes it.
  double point_cam[3];
  ceres::QuaternionRotatePoint(rotation, point_world, point_cam);
  for (int k = 0; k < 3; ++k) point_cam[k] += translation[k];
  // pi and d pi / d X_cam: the model through a 3-variable Jet.
  using Jet3 = ceres::Jet<double, 3>;
  Jet3 jet_params[kMaxNumCameraParams];
  for (int k = 0; k < kMaxNumCameraParams; ++k) jet_params[k] = Jet3(params[k]);
  Jet3 jet_point[3];
  for (int k = 0; k < 3; ++k) jet_point[k] = Jet3(point_cam[k], k);
  Jet3 pixel[2];
  ProjectPoint(model_id, jet_params, jet_point, pixel);
  residual[0] = observed.x() - pixel[0].a;
  residual[1] = observed.y() - pixel[1].a;
  if (!d_rotation && !d_translation && !d_point) return true;
  RowMajor2x3 d_pixel;  // d r / d X_cam = -d pi / d X_cam
  d_pixel.row(0) = -pixel[0].v.transpose();
  d_pixel.row(1) = -pixel[1].v.transpose();
  if (d_translation) RowMajor2x3Map{d_translation} = d_pixel;
  if (d_point) RowMajor2x3Map{d_point} = d_pixel * QuaternionRotationMatrix(rotation);
  if (d_rotation) {
    Eigen::Map<Eigen::Matrix<double, 2, 4, Eigen::RowMajor>> out(d_rotation);
    out = d_pixel * QuaternionRotatePointJacobian(rotation, point_world);
  }
  return true;
}

FisheyeReprojectionCost::FisheyeReprojectionCost(CameraModelId model_id,
                                                 const std::vector<double>& params,
                                                 const Eigen::Vector2d& observed)
    : model_id_(model_id), observed_(observed) {
  CopyParams(params, params_);
}

bool FisheyeReprojectionCost::Evaluate(double const* const* parameters, double* residuals,
                                       double** jacobians) const {
  return EvaluateFisheyeReprojection(model_id_, params_, observed_, parameters[0], parameters[1],
                                     parameters[2], residuals, jacobians ? jacobians[0] : nullptr,
                                     jacobians ? jacobians[1] : nullptr,
                                     jacobians ? jacobians[2] : nullptr);
}

FisheyePoseBlockReprojectionCost::FisheyePoseBlockReprojectionCost(
    CameraModelId model_id, const std::vector<double>& params, const Eigen::Vector2d& observed)
    : model_id_(model_id), observed_(observed) {
  CopyParams(params, params_);
}

bool FisheyePoseBlockReprojectionCost::Evaluate(double const* const* parameters, double* residuals,
                                                double** jacobians) const {
  const double* pose = parameters[0];
  if (!jacobians || !jacobians[0]) {
    return EvaluateFisheyeReprojection(model_id_, params_, observed_, pose, pose + 4, parameters[1],
                                       residuals, nullptr, nullptr,
                                       jacobians ? jacobians[1] : nullptr);
  }
  // The pose block's 2x7 Jacobian: the quaternion's 4 columns, then the translation's 3.
  double d_rotation[8], d_translation[6];
  const bool ok =
      EvaluateFisheyeReprojection(model_id_, params_, observed_, pose, pose + 4, parameters[1],
                                  residuals, d_rotation, d_translation, jacobians[1]);
  for (int row = 0; row < 2; ++row) {
    for (int k = 0; k < 4; ++k) jacobians[0][7 * row + k] = d_rotation[4 * row + k];
    for (int k = 0; k < 3; ++k) jacobians[0][7 * row + 4 + k] = d_translation[3 * row + k];
  }
  return ok;
}

}  // namespace pipescope
