#include "pipescope/geometry/five_point_ransac.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

namespace pipescope {
namespace {

TEST(FivePointRansac, SeparatesOutliersFromAMovingCameraOnAWall) {
  std::mt19937 random(5);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  // Camera 1 at the origin looking along +Z; camera 2 translated 2 cm and turned slightly; the
  // points lie on a curved wall about 0.1 m away.
  const Eigen::AngleAxisd turn(0.02, Eigen::Vector3d(0.3, 1.0, 0.2).normalized());
  const Eigen::Vector3d move(0.02, 0.003, -0.001);
  std::vector<Eigen::Vector3d> first, second;
  std::vector<bool> truth;
  for (int i = 0; i < 300; ++i) {
    const double x = u(random) * 0.12, y = u(random) * 0.09;
    const Eigen::Vector3d point(x, y, 0.1 + 3.0 * (x * x + y * y));
    first.push_back(point.normalized());
    Eigen::Vector3d in_second = turn.inverse() * (point - move);
    const bool outlier = i % 5 == 0;
    if (outlier) in_second += Eigen::Vector3d(u(random), u(random), 0.0) * 0.02;
    second.push_back(in_second.normalized());
    truth.push_back(!outlier);
  }
  FivePointRansacOptions options;
  options.focal_length_px = 700.0;
  std::vector<bool> inlier;
  const int count = FivePointRansacInliers(first, second, options, &inlier);
  int correct_inliers = 0, accepted_outliers = 0;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    if (truth[i] && inlier[i]) ++correct_inliers;
    if (!truth[i] && inlier[i]) ++accepted_outliers;
  }
  EXPECT_EQ(correct_inliers, 240);
  EXPECT_LE(accepted_outliers, 3);  // an outlier may fall on its epipolar line by chance
  EXPECT_EQ(count, correct_inliers + accepted_outliers);
}

TEST(FivePointRansac, RejectsEverythingWithTooFewCorrespondences) {
  std::vector<Eigen::Vector3d> a(4, Eigen::Vector3d::UnitZ()), b(4, Eigen::Vector3d::UnitZ());
  std::vector<bool> inlier;
  EXPECT_EQ(FivePointRansacInliers(a, b, {}, &inlier), 0);
  EXPECT_EQ(inlier, std::vector<bool>(4, false));
}

}  // namespace
}  // namespace pipescope
