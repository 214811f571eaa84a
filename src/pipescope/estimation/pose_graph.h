#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace pipescope {

// 001 §III-E: loop closure as a pose graph. The vertices are the key frames' world_from_cam
// poses (position and unit quaternion); the edges join temporally adjacent key frames (odometry)
// and key frames in the same pipe section visited at different times (loop closures), each with
// a measured relative pose and its information. 001 solves the graph with g2o; here Ceres.
struct PoseGraphEdge {
  int from = 0;
  int to = 0;
  // The measured relative pose T_from^-1 T_to (the `to` camera in the `from` camera's frame).
  Eigen::Isometry3d from_T_to = Eigen::Isometry3d::Identity();
  // Inverse covariance of the 6-D error [translation (m), rotation (rad)], the translation part
  // in the `from` frame; symmetric positive definite.
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Identity();
  // 0: the squared whitened error. Above 0: Huber's loss on it with this scale (in standard
  // deviations), so an edge whose measurement is grossly wrong costs linearly beyond it, and a
  // correction the graph needs goes to that edge rather than being spread over all of them.
  double huber_scale = 0.0;
};

struct PoseGraphOptions {
  int max_iterations = 100;
  double function_tolerance = 1e-12;
  int num_threads = 1;
};

struct PoseGraphResult {
  bool converged = false;     // Ceres ended by one of its convergence tolerances
  double initial_cost = 0.0;  // 0.5 sum of squared whitened errors, as Ceres counts it
  double final_cost = 0.0;
  int iterations = 0;
};

// The information of an edge whose translation has standard deviation `translation_sigma_m` and
// rotation `rotation_sigma_rad` on every axis, independently.
Eigen::Matrix<double, 6, 6> IsotropicPoseInformation(double translation_sigma_m,
                                                     double rotation_sigma_rad);

// Odometry edges i -> i+1 between consecutive poses of `world_from_cam`, each measuring the
// poses' relative pose with IsotropicPoseInformation(translation_sigma_m, rotation_sigma_rad):
// the chain of key frames that loop-closure edges are then added to.
std::vector<PoseGraphEdge> ConsecutivePoseEdges(
    const std::vector<Eigen::Isometry3d>& world_from_cam, double translation_sigma_m,
    double rotation_sigma_rad);

// Moves the poses in `world_from_cam` (in place) to minimise the sum over edges of
//   e^T I e,  e = [t_est - t_meas ; 2 vec(q_meas^-1 q_est)]  (or Huber's loss of it),
// where (t_est, q_est) is the estimated relative pose T_from^-1 T_to. The first pose is held
// constant: it fixes the gauge (the graph alone says nothing about where the world is).
// Throws InputError naming the edge when an index is out of range, an edge joins a pose to
// itself, an information matrix is not symmetric positive definite or a Huber scale is negative
// or not finite.
PoseGraphResult OptimisePoseGraph(const std::vector<PoseGraphEdge>& edges,
                                  std::vector<Eigen::Isometry3d>* world_from_cam,
                                  const PoseGraphOptions& options = {});

}  // namespace pipescope
