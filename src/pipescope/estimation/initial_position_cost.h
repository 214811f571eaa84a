#pragma once

#include <ceres/ceres.h>

#include <Eigen/Geometry>

#include "pipescope/camera/camera.h"
#include "pipescope/estimation/surface_point.h"

namespace pipescope {

// The image-space cost of 000 §5.3.2 (eq. 46-49) for one keypoint seen in key frames a and b
// of the first ten. Every pose there has the start rotation R_0 (world_from_cam) and the
// position (C_X, C_Y, delta_h) (eq. 46). The keypoint's bearing in a meets the wall at X
// (eq. 35-39); X projects into b at u'(g) through the camera model (the original, distorted
// image, as 000 asks); the residual is u'(g) - u(g), the keypoint observed in b (eq. 47).
// Parameters: c_xy[2] shared by all frames, delta_h of a, delta_h of b.
// Differentiated numerically: the wall intersection is geometry/RayToWall's closed form.
class InitialPositionCost {
 public:
  InitialPositionCost(const Camera& camera, const Eigen::Matrix3d& world_from_cam_rotation,
                      const Eigen::Vector3d& bearing_in_a, const Eigen::Vector2d& pixel_in_b,
                      double radius_m)
      : camera_(camera),
        rotation_(world_from_cam_rotation),
        bearing_in_a_(bearing_in_a),
        pixel_in_b_(pixel_in_b),
        radius_m_(radius_m) {}

  bool operator()(const double* c_xy, const double* delta_h_a, const double* delta_h_b,
                  double* residual) const {
    Eigen::Isometry3d world_from_a = Eigen::Isometry3d::Identity();
    world_from_a.linear() = rotation_;
    world_from_a.translation() = Eigen::Vector3d(c_xy[0], c_xy[1], delta_h_a[0]);
    const std::optional<Eigen::Vector3d> wall =
        WallPointOfBearing(world_from_a, bearing_in_a_, radius_m_);
    if (!wall) return false;
    const Eigen::Vector3d position_b(c_xy[0], c_xy[1], delta_h_b[0]);
    const Eigen::Vector3d point_b = rotation_.transpose() * (*wall - position_b);
    Eigen::Vector2d pixel;
    if (camera_.Project(point_b, &pixel) == ProjectionStatus::kBehindCamera) return false;
    residual[0] = pixel.x() - pixel_in_b_.x();
    residual[1] = pixel.y() - pixel_in_b_.y();
    return true;
  }

  static ceres::CostFunction* Create(const Camera& camera,
                                     const Eigen::Matrix3d& world_from_cam_rotation,
                                     const Eigen::Vector3d& bearing_in_a,
                                     const Eigen::Vector2d& pixel_in_b, double radius_m) {
    return new ceres::NumericDiffCostFunction<InitialPositionCost, ceres::CENTRAL, 2, 2, 1, 1>(
        new InitialPositionCost(camera, world_from_cam_rotation, bearing_in_a, pixel_in_b,
                                radius_m));
  }

 private:
  const Camera& camera_;
  Eigen::Matrix3d rotation_;
  Eigen::Vector3d bearing_in_a_;
  Eigen::Vector2d pixel_in_b_;
  double radius_m_;
};

}  // namespace pipescope
