#pragma once

#include <ceres/ceres.h>

#include <Eigen/Geometry>

#include "pipescope/camera/camera.h"
#include "pipescope/estimation/surface_point.h"

namespace pipescope {

// Reprojection through the wall between two key frames with free six-degree-of-freedom poses
// (beyond 000: eq. 47's error with every pose free, the basis of the window adjustment). The
// keypoint's bearing eta_a in key frame a, cast from (q_a, C_a) (world_from_cam, quaternion in
// Eigen's x, y, z, w order), meets the cylinder at X = C_a + kappa R_a eta_a with kappa the
// positive root of eq. 37; X projects into key frame b through the camera model at
//   u' = pi(R_b^T (X - C_b)),
// and the residual is u' - u_b, u_b the keypoint observed in b (distorted pixels). The wall
// point is a function of pose a, so no point parameters are needed: the cylinder is the
// structure. Differentiated numerically (central differences) around geometry/RayToWall.
class CylinderTransferCost {
 public:
  CylinderTransferCost(const Camera& camera, const Eigen::Vector3d& bearing_in_a,
                       const Eigen::Vector2d& pixel_in_b, double radius_m)
      : camera_(camera),
        bearing_in_a_(bearing_in_a),
        pixel_in_b_(pixel_in_b),
        radius_m_(radius_m) {}

  static Eigen::Isometry3d Pose(const double* q, const double* p) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = Eigen::Quaterniond(q[3], q[0], q[1], q[2]).normalized().toRotationMatrix();
    pose.translation() = Eigen::Vector3d(p[0], p[1], p[2]);
    return pose;
  }

  bool operator()(const double* q_a, const double* p_a, const double* q_b, const double* p_b,
                  double* residual) const {
    const std::optional<Eigen::Vector3d> wall =
        WallPointOfBearing(Pose(q_a, p_a), bearing_in_a_, radius_m_);
    if (!wall) return false;
    const Eigen::Vector3d point_b = Pose(q_b, p_b).inverse() * *wall;
    Eigen::Vector2d pixel;
    if (camera_.Project(point_b, &pixel) == ProjectionStatus::kBehindCamera) return false;
    residual[0] = pixel.x() - pixel_in_b_.x();
    residual[1] = pixel.y() - pixel_in_b_.y();
    return true;
  }

  static ceres::CostFunction* Create(const Camera& camera, const Eigen::Vector3d& bearing_in_a,
                                     const Eigen::Vector2d& pixel_in_b, double radius_m) {
    return new ceres::NumericDiffCostFunction<CylinderTransferCost, ceres::CENTRAL, 2, 4, 3, 4, 3>(
        new CylinderTransferCost(camera, bearing_in_a, pixel_in_b, radius_m));
  }

 private:
  const Camera& camera_;
  Eigen::Vector3d bearing_in_a_;
  Eigen::Vector2d pixel_in_b_;
  double radius_m_;
};

// Holds the two symmetries of a straight cylinder, travel along and roll about its axis, for one
// pose: residuals weight (h - h_0) and weight (azimuth of the optical axis - its start value).
// Without it the window adjustment's first window has no gauge.
class CylinderGaugeCost {
 public:
  CylinderGaugeCost(double h0, double azimuth0, double weight)
      : h0_(h0), azimuth0_(azimuth0), weight_(weight) {}

  static double OpticalAxisAzimuth(const Eigen::Matrix3d& world_from_cam) {
    const Eigen::Vector3d axis = world_from_cam.col(2);
    return std::atan2(axis.y(), axis.x());
  }

  bool operator()(const double* q, const double* p, double* residual) const {
    const Eigen::Matrix3d r =
        Eigen::Quaterniond(q[3], q[0], q[1], q[2]).normalized().toRotationMatrix();
    residual[0] = weight_ * (p[2] - h0_);
    residual[1] = weight_ * std::remainder(OpticalAxisAzimuth(r) - azimuth0_, 2.0 * M_PI);
    return true;
  }

  static ceres::CostFunction* Create(double h0, double azimuth0, double weight) {
    return new ceres::NumericDiffCostFunction<CylinderGaugeCost, ceres::CENTRAL, 2, 4, 3>(
        new CylinderGaugeCost(h0, azimuth0, weight));
  }

 private:
  double h0_;
  double azimuth0_;
  double weight_;
};

// A smoothness prior between consecutive key frames (beyond 000): the robot drifts across the
// pipe slowly (millimetres over metres), while the window adjustment sees the position across
// the pipe, and with it the wall distance and the scale, only through the wall's slight
// curvature. Residuals (C_b - C_a)_{x,y} / sigma: each step of the cross-section position costs
// as much as one pixel of reprojection error when it is sigma long.
class CrossSectionSmoothnessCost {
 public:
  explicit CrossSectionSmoothnessCost(double sigma_m) : sigma_m_(sigma_m) {}

  template <typename T>
  bool operator()(const T* p_a, const T* p_b, T* residual) const {
    residual[0] = (p_b[0] - p_a[0]) / sigma_m_;
    residual[1] = (p_b[1] - p_a[1]) / sigma_m_;
    return true;
  }

  static ceres::CostFunction* Create(double sigma_m) {
    return new ceres::AutoDiffCostFunction<CrossSectionSmoothnessCost, 2, 3, 3>(
        new CrossSectionSmoothnessCost(sigma_m));
  }

 private:
  double sigma_m_;
};

// A prior on the camera's place in the cross-section (beyond 000): a crawler is centred in the
// pipe by its wheels, so the camera stays within millimetres of where it was mounted, which is
// what the dense methods assume exactly (000 eq. 19). Residuals (C - anchor)_{x,y} / sigma. It
// holds the level of the wall distance, which the window adjustment sees only through the
// wall's curvature and which otherwise wanders (docs/sparse_vo.md, steel-16in).
class CrossSectionAnchorCost {
 public:
  CrossSectionAnchorCost(const Eigen::Vector2d& anchor_xy, double sigma_m)
      : anchor_xy_(anchor_xy), sigma_m_(sigma_m) {}

  template <typename T>
  bool operator()(const T* p, T* residual) const {
    residual[0] = (p[0] - anchor_xy_.x()) / sigma_m_;
    residual[1] = (p[1] - anchor_xy_.y()) / sigma_m_;
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Vector2d& anchor_xy, double sigma_m) {
    return new ceres::AutoDiffCostFunction<CrossSectionAnchorCost, 2, 3>(
        new CrossSectionAnchorCost(anchor_xy, sigma_m));
  }

 private:
  Eigen::Vector2d anchor_xy_;
  double sigma_m_;
};

}  // namespace pipescope
