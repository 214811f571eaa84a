#include "pipescope/estimation/rigid_point_alignment.h"

#include <gtest/gtest.h>

#include <random>

#include "pipescope/util/error.h"

namespace pipescope {
namespace {

// Wall points of a 0.2 m pipe seen from a second pass: a known motion, 1 mm of noise, and a
// third of the pairs wrong (mismatched descriptors).
TEST(RigidPointAlignment, RecoversAKnownMotionThroughOutliers) {
  std::mt19937_64 random(7);
  std::normal_distribution<double> noise(0.0, 0.001);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * M_PI), along(0.2, 1.0);
  Eigen::Isometry3d truth = Eigen::Isometry3d::Identity();
  truth.linear() = (Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitZ()) *
                    Eigen::AngleAxisd(-0.02, Eigen::Vector3d::UnitX()))
                       .toRotationMatrix();
  truth.translation() = Eigen::Vector3d(0.012, -0.008, 0.031);
  std::vector<Eigen::Vector3d> first, second;
  for (int i = 0; i < 300; ++i) {
    const double a = angle(random);
    const Eigen::Vector3d wall(0.2 * std::cos(a), 0.2 * std::sin(a), along(random));
    Eigen::Vector3d seen = truth.inverse() * wall;
    if (i % 3 == 0) seen = Eigen::Vector3d(0.2 * std::cos(a + 1), 0.2 * std::sin(a + 1), 0.5);
    first.push_back(wall + Eigen::Vector3d(noise(random), noise(random), noise(random)));
    second.push_back(seen);
  }
  const RigidAlignment alignment = AlignPointPairs(first, second);
  ASSERT_TRUE(alignment.found);
  EXPECT_NEAR(static_cast<double>(alignment.inliers.size()), 200.0, 5.0);
  EXPECT_LT((alignment.first_from_second.translation() - truth.translation()).norm(), 0.001);
  const Eigen::AngleAxisd error(alignment.first_from_second.linear().transpose() * truth.linear());
  EXPECT_LT(error.angle(), 0.003);
  EXPECT_NEAR(alignment.rms_m, 0.001 * std::sqrt(3.0), 0.0005);
}

// The second pass's structure at 0.43 of its true size (its odometry lost the scale): with
// the scale free, the rotation and the translation (in the first set's units) still come out.
TEST(RigidPointAlignment, WithScaleRecoversTheMotionOfAShrunkSecondSet) {
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * M_PI), along(0.2, 1.0);
  Eigen::Isometry3d truth = Eigen::Isometry3d::Identity();
  truth.linear() = Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitY()).toRotationMatrix();
  truth.translation() = Eigen::Vector3d(0.02, 0.01, -0.05);
  std::vector<Eigen::Vector3d> first, second;
  for (int i = 0; i < 100; ++i) {
    const double a = angle(random);
    const Eigen::Vector3d wall(0.2 * std::cos(a), 0.2 * std::sin(a), along(random));
    first.push_back(wall);
    second.push_back(0.43 * (truth.inverse() * wall));
  }
  RigidAlignmentOptions options;
  EXPECT_LT(AlignPointPairs(first, second, options).inliers.size(), 50u);  // rigid: no
  options.with_scale = true;
  const RigidAlignment alignment = AlignPointPairs(first, second, options);
  ASSERT_TRUE(alignment.found);
  EXPECT_EQ(alignment.inliers.size(), 100u);
  EXPECT_NEAR(alignment.scale, 1.0 / 0.43, 1e-9);
  EXPECT_LT((alignment.first_from_second.translation() - truth.translation()).norm(), 1e-9);
  EXPECT_LT((alignment.first_from_second.linear() - truth.linear()).norm(), 1e-9);
}

TEST(RigidPointAlignment, TooFewOrCollinearPointsFindNothing) {
  const std::vector<Eigen::Vector3d> line = {{0, 0, 0}, {0, 0, 1}, {0, 0, 2}, {0, 0, 3}};
  EXPECT_FALSE(AlignPointPairs(line, line).found);
  EXPECT_FALSE(AlignPointPairs({{0, 0, 0}, {1, 0, 0}}, {{0, 0, 0}, {1, 0, 0}}).found);
  EXPECT_THROW(AlignPointPairs(line, {{0, 0, 0}}), InputError);
}

}  // namespace
}  // namespace pipescope
