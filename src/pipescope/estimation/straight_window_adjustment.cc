#include "pipescope/estimation/straight_window_adjustment.h"

#include <ceres/ceres.h>
#include <ceres/product_manifold.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "pipescope/estimation/cylinder_axis_prior_error.h"
#include "pipescope/estimation/fisheye_reprojection_cost.h"
#include "pipescope/estimation/fisheye_reprojection_error.h"
#include "pipescope/estimation/least_squares_solve.h"
#include "pipescope/estimation/mad_outliers.h"
#include "pipescope/estimation/straight_cylinder_cost.h"
#include "pipescope/estimation/straight_cylinder_error.h"
#include "pipescope/util/timer.h"

namespace pipescope {
namespace {

Eigen::Vector2d Residual(const Camera& camera, const StraightWindow& window,
                         const WindowObservation& observation) {
  double residual[2];
  FisheyeReprojectionError error(camera.ModelId(), camera.Params(), observation.pixel);
  const WindowPose& pose = window.poses[observation.pose];
  error(pose.rotation, pose.translation, window.points[observation.point].data(), residual);
  return Eigen::Vector2d(residual[0], residual[1]);
}

// RMS reprojection error over the inlier observations of the points the adjustment estimates
// (two or more inlier observations), as the T-intersection adjustment's: a point the MAD stages
// left with one keeps its start while the poses move, so its last observation's error says
// nothing about the solution.
double ImageRms(const Camera& camera, const StraightWindow& window) {
  const std::vector<int> inliers = InlierCounts(window);
  double sum = 0.0;
  int count = 0;
  for (const WindowObservation& observation : window.observations) {
    if (!observation.inlier || inliers[observation.point] < 2) continue;
    sum += Residual(camera, window, observation).squaredNorm();
    ++count;
  }
  return count > 0 ? std::sqrt(sum / count) : 0.0;
}

// RMS distance from the wall over the points the adjustment estimated (two or more inlier
// observations); the others keep their start and say nothing about the solution.
double CylinderRms(const StraightWindowOptions& options, const StraightWindow& window) {
  const StraightCylinderError error(options.radius_m, 1.0);
  const std::vector<int> inliers = InlierCounts(window);
  double sum = 0.0;
  int count = 0;
  for (std::size_t k = 0; k < window.points.size(); ++k) {
    if (inliers[k] < 2) continue;
    double residual;
    error(window.cylinder, window.poses[0].rotation, window.poses[0].translation,
          window.points[k].data(), &residual);
    sum += residual * residual;
    ++count;
  }
  return count > 0 ? std::sqrt(sum / count) : 0.0;
}

// Moves the world origin to `origin` (world coordinates): points and the axis prior shift by
// -origin, and cam_from_world's translation becomes t + R origin, so every camera keeps its
// place and rotation relative to the scene.
void MoveWorldOrigin(const Eigen::Vector3d& origin, StraightWindow* window) {
  for (Eigen::Vector3d& point : window->points) point -= origin;
  for (WindowPose& pose : window->poses) {
    Eigen::Isometry3d cam_from_world = pose.ToIsometry();
    cam_from_world.translation() += cam_from_world.linear() * origin;
    pose = WindowPose::FromIsometry(cam_from_world);
  }
  if (window->axis_prior) window->axis_prior->point -= origin;
}

}  // namespace

std::vector<int> InlierCounts(const std::vector<WindowObservation>& observations,
                              std::size_t num_points) {
  std::vector<int> count(num_points, 0);
  for (const WindowObservation& observation : observations) {
    if (observation.inlier) ++count[observation.point];
  }
  return count;
}

std::vector<int> InlierCounts(const StraightWindow& window) {
  return InlierCounts(window.observations, window.points.size());
}

WindowPose WindowPose::FromIsometry(const Eigen::Isometry3d& cam_from_world) {
  WindowPose pose;
  const Eigen::Quaterniond q(cam_from_world.rotation());
  pose.rotation[0] = q.w();
  pose.rotation[1] = q.x();
  pose.rotation[2] = q.y();
  pose.rotation[3] = q.z();
  for (int k = 0; k < 3; ++k) pose.translation[k] = cam_from_world.translation()(k);
  return pose;
}

Eigen::Isometry3d WindowPose::ToIsometry() const {
  Eigen::Isometry3d result = Eigen::Isometry3d::Identity();
  result.linear() = Eigen::Quaterniond(rotation[0], rotation[1], rotation[2], rotation[3])
                        .normalized()
                        .toRotationMatrix();
  result.translation() = Eigen::Vector3d(translation[0], translation[1], translation[2]);
  return result;
}

std::array<double, 7> WindowPose::ToBlock() const {
  std::array<double, 7> block;
  std::copy(rotation, rotation + 4, block.begin());
  std::copy(translation, translation + 3, block.begin() + 4);
  return block;
}

void WindowPose::SetFromBlock(const std::array<double, 7>& block) {
  std::copy(block.begin(), block.begin() + 4, rotation);
  std::copy(block.begin() + 4, block.end(), translation);
}

double FitStraightCylinder(const StraightWindowOptions& options, StraightWindow* window) {
  if (window->points.empty() || window->poses.empty()) return 0.0;
  ceres::Problem problem;
  for (Eigen::Vector3d& point : window->points) {
    problem.AddResidualBlock(StraightCylinderError::Create(options.radius_m, 1.0),
                             new ceres::HuberLoss(0.01), window->cylinder,
                             window->poses[0].rotation, window->poses[0].translation, point.data());
    problem.SetParameterBlockConstant(point.data());
  }
  problem.SetParameterBlockConstant(window->poses[0].rotation);
  problem.SetParameterBlockConstant(window->poses[0].translation);
  SolveLeastSquares(&problem, ceres::DENSE_QR, 50, 0);
  return CylinderRms(options, *window);
}

StraightWindowSummary OptimiseStraightWindow(const Camera& camera,
                                             const StraightWindowOptions& options,
                                             StraightWindow* window) {
  const Timer timer;
  StraightWindowSummary summary;
  summary.observations = static_cast<int>(window->observations.size());
  summary.initial_rms_px = ImageRms(camera, *window);
  if (window->poses.size() < 2 || window->points.empty()) return summary;
  if (options.use_cylinder) FitStraightCylinder(options, window);
  const bool prior_active = options.use_cylinder && window->axis_prior.has_value();
  // The first camera's centre is the gauge: with it at the origin its translation is zero
  // whatever its rotation, so holding the translation fixed holds the centre even when the
  // axis prior frees the rotation.
  const Eigen::Vector3d first_centre = window->poses[0].ToIsometry().inverse().translation();
  MoveWorldOrigin(first_centre, window);
  double start_rotation[4];
  std::copy(window->poses[0].rotation, window->poses[0].rotation + 4, start_rotation);

  for (int stage = 0; stage < std::max(1, options.stages); ++stage) {
    ceres::Problem::Options problem_options;
    problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(problem_options);
    ceres::QuaternionManifold quaternion_manifold;
    ceres::ProductManifold<ceres::QuaternionManifold, ceres::EuclideanManifold<3>> pose_manifold;
    // Every pose after the first is one 7-parameter block (the first keeps its rotation and
    // translation apart for the gauge and the cylinder terms): the Schur elimination then
    // updates (m + 4)^2 cells of the reduced system per point seen m times instead of
    // (2m + 3)^2, and locks as many mutexes.
    std::vector<std::array<double, 7>> pose_blocks(window->poses.size());
    for (std::size_t k = 1; k < window->poses.size(); ++k) {
      pose_blocks[k] = window->poses[k].ToBlock();
    }
    const std::vector<int> observation_count = InlierCounts(*window);
    for (const WindowObservation& observation : window->observations) {
      if (!observation.inlier || observation_count[observation.point] < 2) continue;
      double* point = window->points[observation.point].data();
      ceres::LossFunction* loss = new ceres::HuberLoss(options.huber_px);
      if (observation.pose == 0) {
        WindowPose& pose = window->poses[0];
        problem.AddResidualBlock(
            new FisheyeReprojectionCost(camera.ModelId(), camera.Params(), observation.pixel), loss,
            pose.rotation, pose.translation, point);
      } else {
        problem.AddResidualBlock(new FisheyePoseBlockReprojectionCost(
                                     camera.ModelId(), camera.Params(), observation.pixel),
                                 loss, pose_blocks[observation.pose].data(), point);
      }
    }
    if (options.use_cylinder) {
      for (std::size_t k = 0; k < window->points.size(); ++k) {
        if (observation_count[k] < 2) continue;
        problem.AddResidualBlock(new StraightCylinderCost(options.radius_m, options.tau),
                                 new ceres::HuberLoss(options.huber_px), window->cylinder,
                                 window->poses[0].rotation, window->poses[0].translation,
                                 window->points[k].data());
      }
      if (prior_active) {
        problem.AddResidualBlock(
            CylinderAxisPriorError::Create(
                window->axis_prior->direction, window->axis_prior->point, start_rotation,
                options.axis_prior_sigma_deg * M_PI / 180.0, options.axis_prior_sigma_m,
                options.first_rotation_sigma_deg * M_PI / 180.0),
            nullptr, window->cylinder, window->poses[0].rotation, window->poses[0].translation);
      }
    }
    if (problem.HasParameterBlock(window->poses[0].rotation)) {
      problem.SetManifold(window->poses[0].rotation, &quaternion_manifold);
    }
    for (std::size_t k = 1; k < pose_blocks.size(); ++k) {
      if (problem.HasParameterBlock(pose_blocks[k].data())) {
        problem.SetManifold(pose_blocks[k].data(), &pose_manifold);
      }
    }
    if (problem.HasParameterBlock(window->poses[0].rotation)) {
      // The gauge: the first pose; with an axis prior only its position (the prior and the
      // pipe's cylinder fix its heading).
      if (!prior_active) problem.SetParameterBlockConstant(window->poses[0].rotation);
      problem.SetParameterBlockConstant(window->poses[0].translation);
    }
    // Once the points are eliminated, the reduced system over the window's poses and the
    // cylinder is nearly dense (every point's cylinder term ties the first pose and the
    // cylinder to every camera that sees it) and small (6 per pose): a dense Cholesky of it is
    // cheaper than building and factoring a block-sparse one.
    const bool last_stage = stage + 1 >= std::max(1, options.stages);
    SolveLeastSquares(&problem, ceres::DENSE_SCHUR,
                      last_stage ? options.max_iterations_per_stage
                                 : options.max_iterations_before_outlier_removal,
                      0, options.num_threads);
    for (std::size_t k = 1; k < window->poses.size(); ++k) {
      window->poses[k].SetFromBlock(pose_blocks[k]);
    }

    if (stage + 1 >= options.stages) break;
    std::vector<std::optional<Eigen::Vector2d>> errors(window->observations.size());
    for (std::size_t k = 0; k < window->observations.size(); ++k) {
      if (window->observations[k].inlier) {
        errors[k] = Residual(camera, *window, window->observations[k]);
      }
    }
    const std::vector<bool> outliers =
        MadOutliers(errors, options.huber_px, options.mad_factor, options.min_mad_px);
    for (std::size_t k = 0; k < window->observations.size(); ++k) {
      if (!outliers[k]) continue;
      window->observations[k].inlier = false;
      ++summary.outliers_removed;
    }
  }
  MoveWorldOrigin(-first_centre, window);
  summary.final_rms_px = ImageRms(camera, *window);
  summary.cylinder_rms_m = options.use_cylinder ? CylinderRms(options, *window) : 0.0;
  summary.seconds = timer.ElapsedSeconds();
  return summary;
}

}  // namespace pipescope
