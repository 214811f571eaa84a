#pragma once

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "pipescope/camera/camera_models.h"
#include "pipescope/geometry/t_intersection.h"

namespace pipescope {

// The residuals of the T-intersection adjustment (001 §III-D) that depend on the model Phi.
// Both hold P_r (cam_from_world) and the fitted cylinders C_r, C_b as constants.
struct TIntersectionConstants {
  Eigen::Isometry3d red_cam_from_world = Eigen::Isometry3d::Identity();
  double red_cylinder[4] = {0, 0, 0, 0};
  double blue_cylinder[4] = {0, 0, 0, 0};
};

// Eq. 3 for an observation in P_b, whose pose is inv(Q) P_r with Q from the model (eq. 8).
// Parameters: the model (5) and the point (3).
class BlueCameraReprojectionError {
 public:
  BlueCameraReprojectionError(const TIntersectionConstants& constants, CameraModelId model_id,
                              const std::vector<double>& params, const Eigen::Vector2d& observed)
      : constants_(constants), model_id_(model_id), observed_(observed) {
    for (int k = 0; k < kMaxNumCameraParams; ++k) {
      params_[k] = k < static_cast<int>(params.size()) ? params[k] : 0.0;
    }
  }

  template <typename T>
  bool operator()(const T* model, const T* point_world, T* residual) const {
    T red_cylinder[4], blue_cylinder[4];
    for (int k = 0; k < 4; ++k) {
      red_cylinder[k] = T(constants_.red_cylinder[k]);
      blue_cylinder[k] = T(constants_.blue_cylinder[k]);
    }
    const Eigen::Matrix<T, 3, 1> point_red = constants_.red_cam_from_world.cast<T>() *
                                             Eigen::Map<const Eigen::Matrix<T, 3, 1>>(point_world);
    const Eigen::Matrix<T, 3, 1> point_blue =
        RedCameraFromBlueCamera(red_cylinder, blue_cylinder, model).inverse() * point_red;
    T params[kMaxNumCameraParams];
    for (int k = 0; k < kMaxNumCameraParams; ++k) params[k] = T(params_[k]);
    T pixel[2];
    ProjectPoint(model_id_, params, point_blue.data(), pixel);
    residual[0] = T(observed_.x()) - pixel[0];
    residual[1] = T(observed_.y()) - pixel[1];
    return true;
  }

  static ceres::CostFunction* Create(const TIntersectionConstants& constants,
                                     CameraModelId model_id, const std::vector<double>& params,
                                     const Eigen::Vector2d& observed) {
    return new ceres::AutoDiffCostFunction<BlueCameraReprojectionError, 2, kTIntersectionParameters,
                                           3>(
        new BlueCameraReprojectionError(constants, model_id, params, observed));
  }

 private:
  TIntersectionConstants constants_;
  CameraModelId model_id_;
  double params_[kMaxNumCameraParams];
  Eigen::Vector2d observed_;
};

// Eq. 6 against one of the two cylinders: sqrt(tau) (sqrt(X~^2 + Y~^2) - r) with X~ the point in
// the red cylinder's frame, or in the blue one's (D^-1 of it) for a point assigned to blue.
// Parameters: for a point on the blue wall the model (5) and the point (3); on the red wall the
// point alone, since C_r and P_r are held and the model does not enter (Create's `blue`).
//
// A second residual, always zero, pads the term to two rows like the reprojection errors, as
// StraightCylinderCost does: with every residual of a point two rows long, Ceres' Schur
// elimination of the points takes its fixed-size <2, 3, dynamic> kernels instead of the
// all-dynamic one. The cost is unchanged.
class TIntersectionCylinderError {
 public:
  TIntersectionCylinderError(const TIntersectionConstants& constants, double radius, double tau)
      : constants_(constants), radius_(radius), sqrt_tau_(std::sqrt(tau)) {}

  template <typename T>
  bool operator()(const T* model, const T* point_world, T* residual) const {
    const Eigen::Matrix<T, 3, 1> point =
        RedCylinderFromBlueCylinder(model).inverse() * InRedCylinder(point_world);
    WallResidual(point, residual);
    return true;
  }

  template <typename T>
  bool operator()(const T* point_world, T* residual) const {
    WallResidual(InRedCylinder(point_world), residual);
    return true;
  }

  static ceres::CostFunction* Create(const TIntersectionConstants& constants, bool blue,
                                     double radius, double tau) {
    auto* error = new TIntersectionCylinderError(constants, radius, tau);
    if (!blue) return new ceres::AutoDiffCostFunction<TIntersectionCylinderError, 2, 3>(error);
    return new ceres::AutoDiffCostFunction<TIntersectionCylinderError, 2, kTIntersectionParameters,
                                           3>(error);
  }

 private:
  template <typename T>
  Eigen::Matrix<T, 3, 1> InRedCylinder(const T* point_world) const {
    T red_cylinder[4];
    for (int k = 0; k < 4; ++k) red_cylinder[k] = T(constants_.red_cylinder[k]);
    return CylinderFromCamera(red_cylinder) *
           (constants_.red_cam_from_world.cast<T>() *
            Eigen::Map<const Eigen::Matrix<T, 3, 1>>(point_world));
  }

  template <typename T>
  void WallResidual(const Eigen::Matrix<T, 3, 1>& point, T* residual) const {
    residual[0] =
        T(sqrt_tau_) *
        (ceres::sqrt(point.x() * point.x() + point.y() * point.y() + T(1e-18)) - T(radius_));
    residual[1] = T(0.0);
  }

  TIntersectionConstants constants_;
  double radius_;
  double sqrt_tau_;
};

}  // namespace pipescope
