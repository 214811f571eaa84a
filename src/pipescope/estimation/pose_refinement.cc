#include "pipescope/estimation/pose_refinement.h"

#include <ceres/ceres.h>

#include "pipescope/estimation/least_squares_solve.h"
#include "pipescope/estimation/surface_consistency_cost.h"

namespace pipescope {

Eigen::Isometry3d RefinePoseOnSurface(const Eigen::Isometry3d& initial,
                                      const std::vector<SurfaceObservation>& observations,
                                      double radius_m, double phi_reference_rad,
                                      const PoseRefinementOptions& options) {
  if (observations.size() < 6) return initial;
  Eigen::Quaterniond rotation(initial.linear());
  rotation.normalize();
  double q[4] = {rotation.x(), rotation.y(), rotation.z(), rotation.w()};
  Eigen::Vector3d position = initial.translation();
  ceres::Problem problem;
  for (const SurfaceObservation& observation : observations) {
    if (!(observation.track.n > 0.0)) continue;
    ceres::LossFunction* loss =
        options.huber_m > 0.0 ? new ceres::HuberLoss(options.huber_m) : nullptr;
    problem.AddResidualBlock(SurfaceConsistencyCost::Create(observation.bearing, observation.track,
                                                            radius_m, phi_reference_rad),
                             loss, q, position.data());
  }
  if (problem.NumResidualBlocks() < 6) return initial;
  problem.SetManifold(q, new ceres::EigenQuaternionManifold);
  if (!SolveLeastSquares(&problem, ceres::DENSE_QR, options.max_iterations, 0).usable) {
    return initial;
  }
  Eigen::Isometry3d refined = Eigen::Isometry3d::Identity();
  refined.linear() = Eigen::Quaterniond(q[3], q[0], q[1], q[2]).normalized().toRotationMatrix();
  refined.translation() = position;
  if (options.max_position_change_radii > 0.0 &&
      (position - initial.translation()).norm() > options.max_position_change_radii * radius_m) {
    return initial;
  }
  return refined;
}

}  // namespace pipescope
