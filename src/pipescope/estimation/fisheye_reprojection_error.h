#pragma once

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/Core>
#include <vector>

#include "pipescope/camera/camera_models.h"

namespace pipescope {

// Image reprojection error of 001 eq. 3, in fisheye image coordinates:
//
//   r = u - u',   u' = pi(R_cw X + t_cw),
//
// where pi is the camera model (for the 001 lens, the polynomial of eq. 1; any model of
// camera_models.h passes since its projection is templated on the scalar), (R_cw, t_cw) is the
// key frame's cam_from_world pose (quaternion w, x, y, z and translation) and X the scene point in
// the world frame. Squared and summed over all valid observations this is epsilon_I. The
// derivatives come from automatic differentiation through the templated projection.
class FisheyeReprojectionError {
 public:
  FisheyeReprojectionError(CameraModelId model_id, const std::vector<double>& params,
                           const Eigen::Vector2d& observed)
      : model_id_(model_id), observed_(observed) {
    for (int k = 0; k < kMaxNumCameraParams; ++k) {
      params_[k] = k < static_cast<int>(params.size()) ? params[k] : 0.0;
    }
  }

  template <typename T>
  bool operator()(const T* cam_from_world_rotation, const T* cam_from_world_translation,
                  const T* point_world, T* residual) const {
    T point_cam[3];
    ceres::QuaternionRotatePoint(cam_from_world_rotation, point_world, point_cam);
    for (int k = 0; k < 3; ++k) point_cam[k] += cam_from_world_translation[k];
    T params[kMaxNumCameraParams];
    for (int k = 0; k < kMaxNumCameraParams; ++k) params[k] = T(params_[k]);
    T pixel[2];
    ProjectPoint(model_id_, params, point_cam, pixel);
    residual[0] = T(observed_.x()) - pixel[0];
    residual[1] = T(observed_.y()) - pixel[1];
    return true;
  }

  static ceres::CostFunction* Create(CameraModelId model_id, const std::vector<double>& params,
                                     const Eigen::Vector2d& observed) {
    return new ceres::AutoDiffCostFunction<FisheyeReprojectionError, 2, 4, 3, 3>(
        new FisheyeReprojectionError(model_id, params, observed));
  }

 private:
  CameraModelId model_id_;
  double params_[kMaxNumCameraParams];
  Eigen::Vector2d observed_;
};

}  // namespace pipescope
