#include "pipescope/geometry/bearing_pnp.h"

#include <gtest/gtest.h>

#include <random>

#include "pipescope/util/error.h"

namespace pipescope {
namespace {

// A forward fisheye in a 0.2 m pipe: wall points up to 70 deg off the axis, a known pose, 0.1
// deg of bearing noise and a quarter of the pairs wrong.
TEST(BearingPnp, RecoversAKnownPoseFromWideBearingsThroughOutliers) {
  std::mt19937_64 random(3);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * M_PI), along(0.1, 1.0);
  std::normal_distribution<double> noise(0.0, 0.1 * M_PI / 180.0);
  Eigen::Isometry3d truth = Eigen::Isometry3d::Identity();
  truth.linear() = (Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()) *
                    Eigen::AngleAxisd(0.03, Eigen::Vector3d::UnitY()))
                       .toRotationMatrix();
  truth.translation() = Eigen::Vector3d(0.01, -0.02, -0.04);
  std::vector<Eigen::Vector3d> points, bearings;
  int wide = 0;
  while (points.size() < 200) {
    const double a = angle(random);
    const Eigen::Vector3d wall(0.2 * std::cos(a), 0.2 * std::sin(a), along(random));
    Eigen::Vector3d bearing = (truth * wall).normalized();
    if (bearing.z() < std::cos(70.0 * M_PI / 180.0)) continue;
    wide += bearing.z() < std::cos(45.0 * M_PI / 180.0);
    bearing = (bearing + Eigen::Vector3d(noise(random), noise(random), noise(random))).normalized();
    if (points.size() % 4 == 0) bearing = Eigen::Vector3d(-bearing.y(), bearing.x(), bearing.z());
    points.push_back(wall);
    bearings.push_back(bearing);
  }
  ASSERT_GT(wide, 20);  // the wide bearings are part of the test
  const BearingPnp pnp = SolveBearingPnp(points, bearings);
  ASSERT_TRUE(pnp.found);
  EXPECT_NEAR(static_cast<double>(pnp.inliers.size()), 150.0, 8.0);
  EXPECT_LT((pnp.cam_from_points.translation() - truth.translation()).norm(), 0.002);
  EXPECT_LT(Eigen::AngleAxisd(pnp.cam_from_points.linear().transpose() * truth.linear()).angle(),
            0.2 * M_PI / 180.0);
  EXPECT_LT(pnp.rms_deg, 0.25);
}

TEST(BearingPnp, TooFewPairsFindNothing) {
  const std::vector<Eigen::Vector3d> points = {{0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
  EXPECT_FALSE(SolveBearingPnp(points, points).found);
  EXPECT_THROW(SolveBearingPnp(points, {{0, 0, 1}}), InputError);
}

}  // namespace
}  // namespace pipescope
