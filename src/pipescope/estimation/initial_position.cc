#include "pipescope/estimation/initial_position.h"

#include <ceres/ceres.h>

#include <cmath>
#include <unordered_map>

#include "pipescope/estimation/initial_position_cost.h"
#include "pipescope/estimation/least_squares_solve.h"

namespace pipescope {

InitialPositionResult OptimiseInitialPosition(
    const Camera& camera, const Eigen::Matrix3d& world_from_cam_rotation, double radius_m,
    const Eigen::Vector2d& c_xy, const std::vector<double>& delta_h,
    const std::vector<std::vector<KeyFrameKeypoint>>& key_frames,
    const InitialPositionOptions& options) {
  InitialPositionResult result;
  result.c_xy = c_xy;
  result.delta_h = delta_h;
  // Where each track is seen: key frame and keypoint.
  std::unordered_map<long long, std::vector<std::pair<int, int>>> sightings;
  for (int a = 0; a < static_cast<int>(key_frames.size()); ++a) {
    for (int i = 0; i < static_cast<int>(key_frames[a].size()); ++i) {
      sightings[key_frames[a][i].track].emplace_back(a, i);
    }
  }
  ceres::Problem problem;
  for (const auto& [track, seen] : sightings) {
    for (const auto& [a, i] : seen) {
      for (const auto& [b, j] : seen) {
        if (a == b) continue;
        ceres::LossFunction* loss =
            options.robust_loss_px > 0.0 ? new ceres::CauchyLoss(options.robust_loss_px) : nullptr;
        problem.AddResidualBlock(
            InitialPositionCost::Create(camera, world_from_cam_rotation, key_frames[a][i].bearing,
                                        key_frames[b][j].pixel, radius_m),
            loss, result.c_xy.data(), &result.delta_h[a], &result.delta_h[b]);
        ++result.residuals;
      }
    }
  }
  if (result.residuals == 0) return result;
  problem.SetParameterBlockConstant(&result.delta_h[0]);
  const LeastSquaresOutcome outcome =
      SolveLeastSquares(&problem, ceres::DENSE_QR, options.max_iterations, result.residuals);
  result.initial_rms_px = outcome.initial_rms;
  result.final_rms_px = outcome.final_rms;
  return result;
}

}  // namespace pipescope
