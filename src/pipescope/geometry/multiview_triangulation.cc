#include "pipescope/geometry/multiview_triangulation.h"

#include <Eigen/Eigenvalues>

namespace pipescope {

bool TriangulateMidpoint(const std::vector<BearingObservation>& observations,
                         Eigen::Vector3d* point, double min_eigenvalue) {
  if (observations.size() < 2) return false;
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d right = Eigen::Vector3d::Zero();
  for (const BearingObservation& observation : observations) {
    const Eigen::Matrix3d world_from_cam_rotation = observation.cam_from_world.linear().transpose();
    const Eigen::Vector3d centre =
        -(world_from_cam_rotation * observation.cam_from_world.translation());
    const Eigen::Vector3d b = (world_from_cam_rotation * observation.bearing).normalized();
    const Eigen::Matrix3d projector = Eigen::Matrix3d::Identity() - b * b.transpose();
    normal += projector;
    right += projector * centre;
  }
  // With n rays the eigenvalues of sum P_i lie in [0, n]; a small one means the rays are nearly
  // parallel and the depth along them is unconstrained.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(normal);
  if (eigen.eigenvalues()(0) < min_eigenvalue * static_cast<double>(observations.size())) {
    return false;
  }
  const Eigen::Vector3d x = normal.ldlt().solve(right);
  for (const BearingObservation& observation : observations) {
    if ((observation.cam_from_world * x).dot(observation.bearing) <= 0.0) return false;
  }
  *point = x;
  return true;
}

}  // namespace pipescope
