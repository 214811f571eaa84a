#include "pipescope/estimation/window_adjustment.h"

#include <ceres/ceres.h>

#include <array>
#include <cmath>

#include "pipescope/estimation/cylinder_transfer_cost.h"
#include "pipescope/estimation/least_squares_solve.h"

namespace pipescope {

WindowAdjustmentSummary AdjustWindow(const Camera& camera, double radius_m,
                                     const WindowAdjustmentOptions& options,
                                     std::vector<WindowKeyFrame>* key_frames) {
  WindowAdjustmentSummary summary;
  const std::size_t count = key_frames->size();
  std::vector<std::array<double, 4>> rotations(count);
  std::vector<std::array<double, 3>> positions(count);
  bool any_fixed = false;
  for (std::size_t a = 0; a < count; ++a) {
    const WindowKeyFrame& key = (*key_frames)[a];
    const Eigen::Quaterniond q = Eigen::Quaterniond(key.pose.linear()).normalized();
    rotations[a] = {q.x(), q.y(), q.z(), q.w()};
    const Eigen::Vector3d p = key.pose.translation();
    positions[a] = {p.x(), p.y(), p.z()};
    any_fixed = any_fixed || key.fixed;
  }
  ceres::Problem problem;
  ForEachLaterSighting(*key_frames, [&](std::size_t a, const KeyFrameKeypoint& reference,
                                        std::size_t b, const KeyFrameKeypoint& seen) {
    if ((*key_frames)[a].fixed && (*key_frames)[b].fixed) return;
    ceres::LossFunction* loss =
        options.robust_loss_px > 0.0 ? new ceres::CauchyLoss(options.robust_loss_px) : nullptr;
    problem.AddResidualBlock(
        CylinderTransferCost::Create(camera, reference.bearing, seen.pixel, radius_m), loss,
        rotations[a].data(), positions[a].data(), rotations[b].data(), positions[b].data());
    ++summary.residuals;
  });
  if (summary.residuals == 0) return summary;
  if (options.cross_section_step_sigma_m > 0.0) {
    for (std::size_t b = 1; b < count; ++b) {
      if ((*key_frames)[b - 1].fixed && (*key_frames)[b].fixed) continue;
      if (!problem.HasParameterBlock(positions[b - 1].data()) ||
          !problem.HasParameterBlock(positions[b].data())) {
        continue;
      }
      problem.AddResidualBlock(
          CrossSectionSmoothnessCost::Create(options.cross_section_step_sigma_m), nullptr,
          positions[b - 1].data(), positions[b].data());
    }
  }
  if (options.cross_section_anchor_sigma_m > 0.0) {
    for (std::size_t a = 0; a < count; ++a) {
      if ((*key_frames)[a].fixed || !problem.HasParameterBlock(positions[a].data())) continue;
      ceres::LossFunction* loss =
          options.cross_section_anchor_robust ? new ceres::CauchyLoss(1.0) : nullptr;
      problem.AddResidualBlock(CrossSectionAnchorCost::Create(options.cross_section_anchor_xy,
                                                              options.cross_section_anchor_sigma_m),
                               loss, positions[a].data());
    }
  }
  for (std::size_t a = 0; a < count; ++a) {
    if (!problem.HasParameterBlock(rotations[a].data())) continue;
    problem.SetManifold(rotations[a].data(), new ceres::EigenQuaternionManifold);
    if ((*key_frames)[a].fixed) {
      problem.SetParameterBlockConstant(rotations[a].data());
      problem.SetParameterBlockConstant(positions[a].data());
    }
  }
  if (!any_fixed && problem.HasParameterBlock(rotations[0].data())) {
    const Eigen::Isometry3d& pose = (*key_frames)[0].pose;
    problem.AddResidualBlock(
        CylinderGaugeCost::Create(pose.translation().z(),
                                  CylinderGaugeCost::OpticalAxisAzimuth(pose.linear()),
                                  options.gauge_weight),
        nullptr, rotations[0].data(), positions[0].data());
    if (options.hold_first_cross_section) {
      problem.SetManifold(positions[0].data(), new ceres::SubsetManifold(3, {0, 1}));
    }
  }
  const LeastSquaresOutcome outcome = SolveLeastSquares(&problem, ceres::DENSE_NORMAL_CHOLESKY,
                                                        options.max_iterations, summary.residuals);
  summary.initial_rms_px = outcome.initial_rms;
  summary.final_rms_px = outcome.final_rms;
  if (!outcome.usable) return summary;
  for (std::size_t a = 0; a < count; ++a) {
    if ((*key_frames)[a].fixed) continue;
    (*key_frames)[a].pose = CylinderTransferCost::Pose(rotations[a].data(), positions[a].data());
  }
  return summary;
}

}  // namespace pipescope
