#include "pipescope/estimation/wall_distance_observability.h"

#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "pipescope/estimation/estimation_testing.h"
#include "pipescope/geometry/pipe_cylinder.h"
#include "pipescope/util/error.h"

namespace pipescope {
namespace {

constexpr double kSixInchRadius = 0.07666;
constexpr double kSixteenInchRadius = 0.19378;

// steel-16in's 640x480 25-degree camera, without distortion.
Camera SixteenInchCamera() {
  const double f = 320.0 / std::tan(12.5 * M_PI / 180.0);
  return Camera(CameraModelId::kPinholeRadtan, 640, 480, {f, f, 319.5, 239.5, 0, 0, 0, 0, 0});
}

// An independent measure of the same quantity: the second view of a camera 1 mm nearer the wall
// fitted, by Ceres's Levenberg-Marquardt over its whole motion (not linearised), to where the
// original camera's second view sees the same wall points' pixels; the RMS left per pixel.
struct MimicCost {
  const Camera* camera;
  Eigen::Isometry3d first;
  Eigen::Vector3d point;
  Eigen::Vector2d target;
  bool operator()(const double* motion, double* residual) const {
    const Eigen::Vector3d rotation_vector(motion[3], motion[4], motion[5]);
    const double angle = rotation_vector.norm();
    const Eigen::Matrix3d turn =
        angle > 0 ? Eigen::AngleAxisd(angle, rotation_vector / angle).toRotationMatrix()
                  : Eigen::Matrix3d::Identity();
    const Eigen::Vector3d centre =
        first.translation() + Eigen::Vector3d(motion[0], motion[1], motion[2]);
    Eigen::Vector2d pixel;
    camera->Project((first.linear() * turn).transpose() * (point - centre), &pixel);
    residual[0] = pixel.x() - target.x();
    residual[1] = pixel.y() - target.y();
    return true;
  }
};

double FittedParallaxPx(const Camera& camera, const Eigen::Isometry3d& start, double radius,
                        double step, double nearer) {
  Eigen::Isometry3d moved = start;
  moved.translation().y() += nearer;  // WallLookingPose faces +Y
  Eigen::Isometry3d second = start;
  second.translation().z() += step;
  ceres::Problem problem;
  double motion[6] = {0, 0, step, 0, 0, 0};
  int count = 0;
  for (int row = 0; row < 15; ++row) {
    for (int col = 0; col < 15; ++col) {
      const Eigen::Vector2d pixel(
          0.05 * (camera.Width() - 1) + 0.9 * (camera.Width() - 1) * col / 14,
          0.05 * (camera.Height() - 1) + 0.9 * (camera.Height() - 1) * row / 14);
      Eigen::Vector3d bearing;
      camera.Unproject(pixel, &bearing);
      const Eigen::Vector3d ray = start.linear() * bearing;
      const Eigen::Vector3d wall0 =
          start.translation() + *RayToWall(start.translation(), ray, radius) * ray;
      const Eigen::Vector3d wall1 =
          moved.translation() + *RayToWall(moved.translation(), ray, radius) * ray;
      Eigen::Vector2d target, check;
      if (camera.Project(second.linear().transpose() * (wall0 - second.translation()), &target) !=
          ProjectionStatus::kValid) {
        continue;
      }
      ++count;
      problem.AddResidualBlock(new ceres::NumericDiffCostFunction<MimicCost, ceres::CENTRAL, 2, 6>(
                                   new MimicCost{&camera, moved, wall1, target}),
                               nullptr, motion);
    }
  }
  ceres::Solver::Options options;
  options.function_tolerance = 1e-16;
  options.parameter_tolerance = 1e-16;
  options.gradient_tolerance = 1e-16;
  options.max_num_iterations = 200;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  return std::sqrt(2.0 * summary.final_cost / count);
}

TEST(WallDistanceObservability, WideViewSeesTheWallDistanceNarrowViewDoesNot) {
  const WallDistanceObservability six = AssessWallDistanceObservability(
      SteelSixInchCamera(), WallLookingPose(Eigen::Vector3d::Zero()), kSixInchRadius);
  const WallDistanceObservability sixteen = AssessWallDistanceObservability(
      SixteenInchCamera(), WallLookingPose(Eigen::Vector3d::Zero()), kSixteenInchRadius);
  std::printf(
      "6-inch 70 deg: %.4f px/mm, sigma %.3f mm (%.3f %%); 16-inch 25 deg: %.4f px/mm, "
      "sigma %.3f mm (%.3f %%)\n",
      six.parallax_px_per_mm, six.wall_distance_sigma_mm, six.scale_sigma_pct,
      sixteen.parallax_px_per_mm, sixteen.wall_distance_sigma_mm, sixteen.scale_sigma_pct);
  EXPECT_TRUE(six.observable);
  EXPECT_FALSE(sixteen.observable);
  EXPECT_GT(six.parallax_px_per_mm, 5.0 * sixteen.parallax_px_per_mm);
}

TEST(WallDistanceObservability, FlatWallHidesTheWallDistance) {
  // A 100 m pipe seen from 77 mm: the wall is a plane to the camera.
  const double radius = 100.0;
  const WallDistanceObservability flat = AssessWallDistanceObservability(
      SteelSixInchCamera(), WallLookingPose(Eigen::Vector3d(0, radius - 0.07666, 0)), radius);
  EXPECT_LT(flat.parallax_px_per_mm, 1e-3);
  EXPECT_FALSE(flat.observable);
}

TEST(WallDistanceObservability, AgreesWithANonlinearFitOfTheSecondView) {
  for (const auto& [camera, radius] : {std::pair{SteelSixInchCamera(), kSixInchRadius},
                                       std::pair{SixteenInchCamera(), kSixteenInchRadius}}) {
    const Eigen::Isometry3d start = WallLookingPose(Eigen::Vector3d::Zero());
    const WallDistanceObservability assessed =
        AssessWallDistanceObservability(camera, start, radius);
    const double fitted = FittedParallaxPx(camera, start, radius, assessed.step_m, 0.001);
    std::printf("assessed %.5f px/mm, fitted %.5f px for 1 mm\n", assessed.parallax_px_per_mm,
                fitted);
    EXPECT_NEAR(fitted, assessed.parallax_px_per_mm, 0.05 * assessed.parallax_px_per_mm);
  }
}

TEST(WallDistanceObservability, ForwardCameraIsRefused) {
  EXPECT_THROW(AssessWallDistanceObservability(SteelSixInchCamera(), Eigen::Isometry3d::Identity(),
                                               kSixInchRadius),
               InputError);
}

}  // namespace
}  // namespace pipescope
