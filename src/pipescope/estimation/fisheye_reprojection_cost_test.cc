#include "pipescope/estimation/fisheye_reprojection_cost.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>
#include <vector>

#include "pipescope/estimation/fisheye_reprojection_error.h"

namespace pipescope {
namespace {

struct ModelCase {
  CameraModelId id;
  std::vector<double> params;
};

// One calibration per model: pinhole-radtan (EuRoC-like), Kannala-Brandt, and the 190-degree
// fisheye polynomial of 001 §II.
std::vector<ModelCase> Models() {
  return {
      {CameraModelId::kPinholeRadtan,
       {458.654, 457.296, 367.215, 248.375, -0.2834, 0.07396, 0.00019, 1.76e-05, -0.0012}},
      {CameraModelId::kKannalaBrandt, {280.3, 279.8, 319.1, 240.6, -0.013, 0.021, -0.012, 0.0025}},
      {CameraModelId::kFisheyePoly, {291.72, -2.917, 0.0, 0.0, 639.5, 479.5}}};
}

// The analytic Jacobians equal automatic differentiation of FisheyeReprojectionError (same
// residual, bit for bit) for random poses with non-unit quaternions and points in front of the
// camera, beside it (fisheye models, past 90 degrees) and near the optical axis.
TEST(FisheyeReprojectionCostTest, JacobiansEqualAutomaticDifferentiation) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (const ModelCase& model : Models()) {
    const bool wide = model.id != CameraModelId::kPinholeRadtan;
    for (int trial = 0; trial < 200; ++trial) {
      double rotation[4];
      for (double& value : rotation) value = uniform(rng);
      const double scale = 0.5 + 1.5 * std::abs(uniform(rng));  // |q| != 1
      const Eigen::Vector4d q = Eigen::Map<Eigen::Vector4d>(rotation).normalized() * scale;
      for (int k = 0; k < 4; ++k) rotation[k] = q(k);
      double translation[3] = {uniform(rng), uniform(rng), uniform(rng)};
      // A point in the camera frame, then moved to the world by the inverse pose.
      Eigen::Vector3d cam(uniform(rng), uniform(rng),
                          wide ? uniform(rng) : 1.0 + uniform(rng) + 1.0);
      if (trial % 10 == 0) cam = Eigen::Vector3d(1e-4 * uniform(rng), 1e-4 * uniform(rng), 1.0);
      const Eigen::Quaterniond unit(q(0), q(1), q(2), q(3));
      const Eigen::Vector3d world =
          unit.normalized().inverse() * (cam - Eigen::Map<Eigen::Vector3d>(translation));
      double point[3] = {world.x(), world.y(), world.z()};
      const Eigen::Vector2d observed(300 + 100 * uniform(rng), 250 + 100 * uniform(rng));

      ceres::AutoDiffCostFunction<FisheyeReprojectionError, 2, 4, 3, 3> automatic(
          new FisheyeReprojectionError(model.id, model.params, observed));
      const FisheyeReprojectionCost analytic(model.id, model.params, observed);
      const double* parameters[3] = {rotation, translation, point};
      double residual_a[2], residual_b[2];
      double ja_q[8], ja_t[6], ja_x[6], jb_q[8], jb_t[6], jb_x[6];
      double* jacobians_a[3] = {ja_q, ja_t, ja_x};
      double* jacobians_b[3] = {jb_q, jb_t, jb_x};
      ASSERT_TRUE(automatic.Evaluate(parameters, residual_a, jacobians_a));
      ASSERT_TRUE(analytic.Evaluate(parameters, residual_b, jacobians_b));
      EXPECT_EQ(residual_a[0], residual_b[0]);
      EXPECT_EQ(residual_a[1], residual_b[1]);
      double largest = 0.0;
      for (int k = 0; k < 8; ++k) largest = std::max(largest, std::abs(ja_q[k]));
      for (int k = 0; k < 6; ++k)
        largest = std::max({largest, std::abs(ja_t[k]), std::abs(ja_x[k])});
      const double tolerance = 1e-10 * std::max(1.0, largest);
      for (int k = 0; k < 8; ++k) EXPECT_NEAR(ja_q[k], jb_q[k], tolerance) << trial << " q " << k;
      for (int k = 0; k < 6; ++k) {
        EXPECT_NEAR(ja_t[k], jb_t[k], tolerance) << trial << " t " << k;
        EXPECT_NEAR(ja_x[k], jb_x[k], tolerance) << trial << " X " << k;
      }

      // The pose-block form: quaternion and translation in one 7-vector, the same numbers.
      const FisheyePoseBlockReprojectionCost block(model.id, model.params, observed);
      double pose[7];
      for (int k = 0; k < 4; ++k) pose[k] = rotation[k];
      for (int k = 0; k < 3; ++k) pose[4 + k] = translation[k];
      const double* block_parameters[2] = {pose, point};
      double residual_c[2], jc_pose[14], jc_x[6];
      double* jacobians_c[2] = {jc_pose, jc_x};
      ASSERT_TRUE(block.Evaluate(block_parameters, residual_c, jacobians_c));
      EXPECT_EQ(residual_c[0], residual_b[0]);
      EXPECT_EQ(residual_c[1], residual_b[1]);
      for (int row = 0; row < 2; ++row) {
        for (int k = 0; k < 4; ++k) EXPECT_EQ(jc_pose[7 * row + k], jb_q[4 * row + k]);
        for (int k = 0; k < 3; ++k) {
          EXPECT_EQ(jc_pose[7 * row + 4 + k], jb_t[3 * row + k]);
          EXPECT_EQ(jc_x[3 * row + k], jb_x[3 * row + k]);
        }
      }
    }
  }
}

}  // namespace
}  // namespace pipescope
