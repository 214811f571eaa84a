#include "pipescope/estimation/t_intersection_adjustment.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "pipescope/estimation/fisheye_reprojection_cost.h"
#include "pipescope/estimation/fisheye_reprojection_error.h"
#include "pipescope/estimation/least_squares_solve.h"
#include "pipescope/estimation/mad_outliers.h"
#include "pipescope/estimation/t_intersection_errors.h"
#include "pipescope/util/timer.h"

namespace pipescope {
namespace {

TIntersectionConstants Constants(const TIntersectionProblem& problem) {
  TIntersectionConstants constants;
  constants.red_cam_from_world = problem.poses.front().ToIsometry();
  std::copy(problem.red_cylinder, problem.red_cylinder + 4, constants.red_cylinder);
  std::copy(problem.blue_cylinder, problem.blue_cylinder + 4, constants.blue_cylinder);
  return constants;
}

Eigen::Vector2d Residual(const Camera& camera, const TIntersectionProblem& problem,
                         const WindowObservation& observation) {
  WindowPose pose = problem.poses[observation.pose];
  if (observation.pose + 1 == static_cast<int>(problem.poses.size())) {
    pose = WindowPose::FromIsometry(BlueCamFromWorld(problem));
  }
  double residual[2];
  FisheyeReprojectionError error(camera.ModelId(), camera.Params(), observation.pixel);
  error(pose.rotation, pose.translation, problem.points[observation.point].data(), residual);
  return Eigen::Vector2d(residual[0], residual[1]);
}

// Over the inlier observations of the points the adjustment estimates (two or more inlier
// observations). A point the outlier removal left with one keeps its start while the poses
// move, so its last observation says nothing about the solution: on route A's T2 75 such
// observations at 47 px RMS raised the RMS of 47 500 others at 0.40 px to 1.9 px.
double ImageRms(const Camera& camera, const TIntersectionProblem& problem) {
  const std::vector<int> counts = InlierCounts(problem.observations, problem.points.size());
  double sum = 0.0;
  int count = 0;
  for (const WindowObservation& observation : problem.observations) {
    if (!observation.inlier || counts[observation.point] < 2) continue;
    sum += Residual(camera, problem, observation).squaredNorm();
    ++count;
  }
  return count > 0 ? std::sqrt(sum / count) : 0.0;
}

// The cylinder each point belongs to (Fig. 4c) and its distance from that wall.
struct Assignment {
  bool blue = false;
  double distance_m = 0.0;
};

Assignment Assign(const TIntersectionProblem& problem, const Eigen::Vector3d& point_world,
                  double radius_m) {
  const Eigen::Vector3d point_red =
      CylinderFromCamera(problem.red_cylinder) * (problem.poses.front().ToIsometry() * point_world);
  Assignment assignment;
  assignment.blue =
      NearerIsBlueCylinder(point_red, problem.model, radius_m, &assignment.distance_m);
  return assignment;
}

// 001 §III-C's outlier removal, used again in §III-D. Returns how many it removed.
int RemoveOutliers(const Camera& camera, const TIntersectionOptions& options,
                   TIntersectionProblem* problem) {
  std::vector<std::optional<Eigen::Vector2d>> errors(problem->observations.size());
  for (std::size_t k = 0; k < problem->observations.size(); ++k) {
    if (problem->observations[k].inlier) {
      errors[k] = Residual(camera, *problem, problem->observations[k]);
    }
  }
  const std::vector<bool> outliers =
      MadOutliers(errors, options.huber_px, options.mad_factor, options.min_mad_px);
  int removed = 0;
  for (std::size_t k = 0; k < problem->observations.size(); ++k) {
    if (!outliers[k]) continue;
    problem->observations[k].inlier = false;
    ++removed;
  }
  return removed;
}

std::vector<int> InlierCounts(const TIntersectionProblem& problem) {
  return InlierCounts(problem.observations, problem.points.size());
}

}  // namespace

Eigen::Isometry3d BlueCamFromWorld(const TIntersectionProblem& problem) {
  const Eigen::Isometry3d red_from_blue =
      RedCameraFromBlueCamera(problem.red_cylinder, problem.blue_cylinder, problem.model);
  return red_from_blue.inverse() * problem.poses.front().ToIsometry();
}

TIntersectionSummary OptimiseTIntersection(const Camera& camera,
                                           const TIntersectionOptions& options,
                                           TIntersectionProblem* problem) {
  const Timer timer;
  TIntersectionSummary summary;
  summary.observations = static_cast<int>(problem->observations.size());
  const int num_poses = static_cast<int>(problem->poses.size());
  if (num_poses < 2 || problem->points.empty()) return summary;
  problem->poses.back() = WindowPose::FromIsometry(BlueCamFromWorld(*problem));
  summary.initial_rms_px = ImageRms(camera, *problem);
  const TIntersectionConstants constants = Constants(*problem);
  const int blue_index = num_poses - 1;
  const int stages = std::max(1, options.stages);

  for (int stage = 0; stage < stages; ++stage) {
    ceres::Problem::Options problem_options;
    problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem ceres_problem(problem_options);
    ceres::ProductManifold<ceres::QuaternionManifold, ceres::EuclideanManifold<3>> pose_manifold;
    // Each pose before P_b is one 7-parameter block (quaternion, translation) with eq. 3's
    // Jacobians written out, as in the straight windows: the Schur elimination then updates
    // about (m + 1)^2 cells of the reduced system per point seen m times (the model its +1)
    // instead of (2m + 1)^2.
    std::vector<std::array<double, 7>> pose_blocks(blue_index);
    for (int p = 0; p < blue_index; ++p) pose_blocks[p] = problem->poses[p].ToBlock();
    const std::vector<int> counts = InlierCounts(*problem);
    for (const WindowObservation& observation : problem->observations) {
      if (!observation.inlier || counts[observation.point] < 2) continue;
      double* point = problem->points[observation.point].data();
      ceres::LossFunction* loss = new ceres::HuberLoss(options.huber_px);
      if (observation.pose == blue_index) {
        ceres_problem.AddResidualBlock(
            BlueCameraReprojectionError::Create(constants, camera.ModelId(), camera.Params(),
                                                observation.pixel),
            loss, problem->model, point);
      } else {
        ceres_problem.AddResidualBlock(
            new FisheyePoseBlockReprojectionCost(camera.ModelId(), camera.Params(),
                                                 observation.pixel),
            loss, pose_blocks[observation.pose].data(), point);
      }
    }
    // Each estimated point against the wall nearer to it now (Fig. 4c); the assignment is
    // renewed at every stage as the model moves. Huber on sqrt(tau) e with the image term's
    // threshold, as the straight windows do.
    for (std::size_t k = 0; k < problem->points.size(); ++k) {
      if (counts[k] < 2) continue;
      const bool blue = Assign(*problem, problem->points[k], options.radius_m).blue;
      ceres::CostFunction* wall =
          TIntersectionCylinderError::Create(constants, blue, options.radius_m, options.tau);
      ceres::LossFunction* loss = new ceres::HuberLoss(options.huber_px);
      if (blue) {
        ceres_problem.AddResidualBlock(wall, loss, problem->model, problem->points[k].data());
      } else {
        ceres_problem.AddResidualBlock(wall, loss, problem->points[k].data());
      }
    }
    for (int p = 0; p < blue_index; ++p) {
      double* pose = pose_blocks[p].data();
      if (!ceres_problem.HasParameterBlock(pose)) continue;
      ceres_problem.SetManifold(pose, &pose_manifold);
      if (p == 0) ceres_problem.SetParameterBlockConstant(pose);  // P_r: the gauge
    }
    if (!ceres_problem.HasParameterBlock(problem->model)) break;
    ceres::SubsetManifold held_phi(kTIntersectionParameters, {kPhi});
    if (options.hold_phi) ceres_problem.SetManifold(problem->model, &held_phi);
    const LeastSquaresOutcome outcome =
        SolveLeastSquares(&ceres_problem, ceres::DENSE_SCHUR, options.max_iterations_per_stage, 0,
                          options.num_threads);
    summary.usable = outcome.usable;
    summary.schur_structure = outcome.schur_structure;
    summary.stage_iterations.push_back(outcome.iterations);
    for (int p = 1; p < blue_index; ++p) problem->poses[p].SetFromBlock(pose_blocks[p]);
    problem->poses.back() = WindowPose::FromIsometry(BlueCamFromWorld(*problem));
    if (stage + 1 < stages) summary.outliers_removed += RemoveOutliers(camera, options, problem);
  }

  summary.final_rms_px = ImageRms(camera, *problem);
  const std::vector<int> counts = InlierCounts(*problem);
  double sum = 0.0;
  int count = 0;
  for (std::size_t k = 0; k < problem->points.size(); ++k) {
    if (counts[k] < 2) continue;
    const Assignment assignment = Assign(*problem, problem->points[k], options.radius_m);
    (assignment.blue ? summary.blue_points : summary.red_points) += 1;
    sum += assignment.distance_m * assignment.distance_m;
    ++count;
  }
  summary.cylinder_rms_m = count > 0 ? std::sqrt(sum / count) : 0.0;
  summary.seconds = timer.ElapsedSeconds();
  return summary;
}

}  // namespace pipescope
