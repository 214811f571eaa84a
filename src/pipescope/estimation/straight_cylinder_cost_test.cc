#include "pipescope/estimation/straight_cylinder_cost.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <random>

#include "pipescope/estimation/straight_cylinder_error.h"

namespace pipescope {
namespace {

// The analytic Jacobians equal automatic differentiation of StraightCylinderError (same
// residual, bit for bit) for random cylinders, non-unit first-pose quaternions and points; the
// padding row is zero with zero derivatives.
TEST(StraightCylinderCostTest, JacobiansEqualAutomaticDifferentiation) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const double radius = 0.2, tau = 2.5e5;
  ceres::AutoDiffCostFunction<StraightCylinderError, 1, 4, 4, 3, 3> automatic(
      new StraightCylinderError(radius, tau));
  const StraightCylinderCost analytic(radius, tau);
  for (int trial = 0; trial < 500; ++trial) {
    double cylinder[4] = {0.5 * uniform(rng), 0.5 * uniform(rng), 0.1 * uniform(rng),
                          0.1 * uniform(rng)};
    double rotation[4];
    for (double& value : rotation) value = uniform(rng);
    const double scale = (0.5 + 1.5 * std::abs(uniform(rng))) /
                         Eigen::Map<Eigen::Vector4d>(rotation).norm();  // |q| != 1
    for (double& value : rotation) value *= scale;
    double translation[3] = {0.3 * uniform(rng), 0.3 * uniform(rng), 0.3 * uniform(rng)};
    double point[3] = {0.3 * uniform(rng), 0.3 * uniform(rng), 2.0 * uniform(rng)};
    const double* parameters[4] = {cylinder, rotation, translation, point};
    double residual_a, residual_b[2];
    double ja[4][4], jb[4][8];
    double* jacobians_a[4] = {ja[0], ja[1], ja[2], ja[3]};
    double* jacobians_b[4] = {jb[0], jb[1], jb[2], jb[3]};
    ASSERT_TRUE(automatic.Evaluate(parameters, &residual_a, jacobians_a));
    for (auto& row : jb) std::fill_n(row, 8, 1.0);
    ASSERT_TRUE(analytic.Evaluate(parameters, residual_b, jacobians_b));
    EXPECT_EQ(residual_a, residual_b[0]);
    EXPECT_EQ(residual_b[1], 0.0);
    const int sizes[4] = {4, 4, 3, 3};
    for (int block = 0; block < 4; ++block) {
      for (int k = 0; k < sizes[block]; ++k) {
        EXPECT_NEAR(ja[block][k], jb[block][k], 1e-9 * std::max(1.0, std::abs(ja[block][k])))
            << "trial " << trial << " block " << block << " entry " << k;
        EXPECT_EQ(jb[block][sizes[block] + k], 0.0);
      }
    }
  }
}

}  // namespace
}  // namespace pipescope
