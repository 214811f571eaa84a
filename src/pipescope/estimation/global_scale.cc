#include "pipescope/estimation/global_scale.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>

#include "pipescope/estimation/least_squares_solve.h"
#include "pipescope/estimation/surface_point.h"

namespace pipescope {
namespace {

// Residual of one transfer a -> b (CylinderTransferCost) with both poses moved by the common
// correction theta = (dX, dY, s): C' = (C_X + dX, C_Y + dY, h_0 + s (C_h - h_0)).
class GlobalScaleCost {
 public:
  GlobalScaleCost(const Camera& camera, const Eigen::Isometry3d& a, const Eigen::Isometry3d& b,
                  const Eigen::Vector3d& bearing_in_a, const Eigen::Vector2d& pixel_in_b, double h0,
                  double radius_m)
      : camera_(camera),
        a_(a),
        b_(b),
        bearing_in_a_(bearing_in_a),
        pixel_in_b_(pixel_in_b),
        h0_(h0),
        radius_m_(radius_m) {}

  Eigen::Isometry3d Moved(const Eigen::Isometry3d& pose, const double* theta) const {
    Eigen::Isometry3d moved = pose;
    const Eigen::Vector3d c = pose.translation();
    moved.translation() =
        Eigen::Vector3d(c.x() + theta[0], c.y() + theta[1], h0_ + theta[2] * (c.z() - h0_));
    return moved;
  }

  bool operator()(const double* theta, double* residual) const {
    const std::optional<Eigen::Vector3d> wall =
        WallPointOfBearing(Moved(a_, theta), bearing_in_a_, radius_m_);
    if (!wall) return false;
    Eigen::Vector2d pixel;
    if (camera_.Project(Moved(b_, theta).inverse() * *wall, &pixel) ==
        ProjectionStatus::kBehindCamera) {
      return false;
    }
    residual[0] = pixel.x() - pixel_in_b_.x();
    residual[1] = pixel.y() - pixel_in_b_.y();
    return true;
  }

 private:
  const Camera& camera_;
  Eigen::Isometry3d a_, b_;
  Eigen::Vector3d bearing_in_a_;
  Eigen::Vector2d pixel_in_b_;
  double h0_;
  double radius_m_;
};

}  // namespace

GlobalScaleResult CorrectGlobalScale(const Camera& camera, double radius_m,
                                     const GlobalScaleOptions& options,
                                     std::vector<WindowKeyFrame>* key_frames) {
  GlobalScaleResult result;
  if (key_frames->size() < 2) return result;
  const double h0 = key_frames->front().pose.translation().z();
  double theta[3] = {0.0, 0.0, 1.0};
  ceres::Problem problem;
  const std::size_t stride = std::max(1, options.reference_stride);
  ForEachLaterSighting(*key_frames, [&](std::size_t a, const KeyFrameKeypoint& reference,
                                        std::size_t b, const KeyFrameKeypoint& seen) {
    if (a % stride != 0) return;
    ceres::LossFunction* loss =
        options.robust_loss_px > 0.0 ? new ceres::CauchyLoss(options.robust_loss_px) : nullptr;
    problem.AddResidualBlock(
        new ceres::NumericDiffCostFunction<GlobalScaleCost, ceres::CENTRAL, 2, 3>(
            new GlobalScaleCost(camera, (*key_frames)[a].pose, (*key_frames)[b].pose,
                                reference.bearing, seen.pixel, h0, radius_m)),
        loss, theta);
    ++result.residuals;
  });
  if (result.residuals == 0) return result;
  const LeastSquaresOutcome outcome =
      SolveLeastSquares(&problem, ceres::DENSE_QR, options.max_iterations, result.residuals);
  result.initial_rms_px = outcome.initial_rms;
  result.final_rms_px = outcome.final_rms;
  if (!outcome.usable) return result;
  result.offset_xy = Eigen::Vector2d(theta[0], theta[1]);
  result.scale = theta[2];
  for (WindowKeyFrame& key : *key_frames) {
    const Eigen::Vector3d c = key.pose.translation();
    key.pose.translation() =
        Eigen::Vector3d(c.x() + theta[0], c.y() + theta[1], h0 + theta[2] * (c.z() - h0));
  }
  return result;
}

}  // namespace pipescope
