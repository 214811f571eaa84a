#include "pipescope/estimation/mad_outliers.h"

#include <gtest/gtest.h>

#include <cmath>

namespace pipescope {
namespace {

TEST(MadOutliers, FlagsTheErrorFarFromTheRestAndSkipsTheRemoved) {
  // Components 0.1 k: median and MAD worked by hand below; one gross error, one already removed.
  std::vector<std::optional<Eigen::Vector2d>> errors;
  for (int k = -5; k <= 5; ++k) errors.push_back(Eigen::Vector2d(0.1 * k, -0.1 * k));
  errors.push_back(Eigen::Vector2d(1.0, 0.0));   // within 3 MAD? see below
  errors.push_back(Eigen::Vector2d(40.0, 0.0));  // Huber-weighted: sqrt(2 / 40) * 40 = 8.94
  errors.push_back(std::nullopt);
  const std::vector<bool> outliers = MadOutliers(errors, 2.0, 3.0, 0.1);
  ASSERT_EQ(outliers.size(), errors.size());
  // 26 components: 22 of +-0.1 k, then 1, 0, 8.94, 0; the upper median is 0 and the deviations'
  // upper median 0.3, so 3 * 1.4826 * 0.3 = 1.33 is the limit.
  for (int k = 0; k < 11; ++k) EXPECT_FALSE(outliers[k]) << k;
  EXPECT_FALSE(outliers[11]);
  EXPECT_TRUE(outliers[12]);
  EXPECT_FALSE(outliers[13]);
}

TEST(MadOutliers, TheFloorKeepsANearPerfectSet) {
  std::vector<std::optional<Eigen::Vector2d>> errors(20, Eigen::Vector2d(0.0, 0.0));
  errors[3] = Eigen::Vector2d(0.25, 0.0);  // MAD 0: only the floor (0.1 * 1 ... 3 * 0.1) decides
  EXPECT_FALSE(MadOutliers(errors, 2.0, 3.0, 0.1)[3]);
  EXPECT_TRUE(MadOutliers(errors, 2.0, 3.0, 0.05)[3]);
}

}  // namespace
}  // namespace pipescope
