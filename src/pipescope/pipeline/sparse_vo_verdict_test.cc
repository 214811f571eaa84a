#include "pipescope/pipeline/sparse_vo_verdict.h"

#include <gtest/gtest.h>

namespace pipescope {
namespace {

constexpr double kRadius = 0.07666;

// A run that measures its wall distance, whose key frames each track `tracked` keypoints (the
// first tracks none) and whose camera strays `excursion_m` across the pipe.
SparseVoResult SparseRun(int tracked, double excursion_m, bool view_observes = true) {
  SparseVoResult result;
  result.wall_distance.start_m = kRadius;
  result.wall_distance.method_measures = true;
  result.wall_distance.observability = WallDistanceObservability();
  result.wall_distance.observability->observable = view_observes;
  result.cross_section_excursion_m = excursion_m;
  result.summary.key_frame_records.push_back({0, 500, 0});
  for (int k = 1; k <= 9; ++k) {
    result.summary.key_frame_records.push_back({static_cast<std::size_t>(10 * k), 500, tracked});
  }
  return result;
}

bool Says(const std::vector<std::string>& reasons, const std::string& text) {
  for (const std::string& reason : reasons) {
    if (reason.find(text) != std::string::npos) return true;
  }
  return false;
}

TEST(SparseVoVerdict, AWellTrackedRunNearItsStartHasNoReason) {
  EXPECT_TRUE(SparseVoVerdictReasons(SparseRun(300, 0.004), SparseVoOptions{}, kRadius).empty());
}

TEST(SparseVoVerdict, ThinTracksMakeTheRunUnreliable) {
  // The median is over the key frames after the first: 9 at 74 is below 75, at 75 not.
  const std::vector<std::string> reasons =
      SparseVoVerdictReasons(SparseRun(74, 0.004), SparseVoOptions{}, kRadius);
  ASSERT_EQ(reasons.size(), 1u);
  EXPECT_TRUE(Says(reasons, "track a median of 74 keypoints (limit 75)"));
  EXPECT_TRUE(SparseVoVerdictReasons(SparseRun(75, 0.004), SparseVoOptions{}, kRadius).empty());
  SparseVoOptions off;
  off.min_median_tracked = 0;
  EXPECT_TRUE(SparseVoVerdictReasons(SparseRun(10, 0.004), off, kRadius).empty());
}

TEST(SparseVoVerdict, StrayingAcrossThePipeMakesTheRunUnreliable) {
  // 25 % of the radius: 19.2 mm.
  EXPECT_TRUE(Says(SparseVoVerdictReasons(SparseRun(300, 0.020), SparseVoOptions{}, kRadius),
                   "strays 20.0 mm across the pipe from its start"));
  EXPECT_TRUE(SparseVoVerdictReasons(SparseRun(300, 0.019), SparseVoOptions{}, kRadius).empty());
}

TEST(SparseVoVerdict, AnExcursionTheViewCannotSeeCountsFromTwoPercent) {
  // 2 % of the 76.66 mm wall distance: 1.53 mm.
  EXPECT_TRUE(
      Says(SparseVoVerdictReasons(SparseRun(300, 0.0016, false), SparseVoOptions{}, kRadius),
           "this view cannot measure"));
  EXPECT_TRUE(
      SparseVoVerdictReasons(SparseRun(300, 0.0015, false), SparseVoOptions{}, kRadius).empty());
  // Where the view measures it, the same excursion is the crawler's.
  EXPECT_TRUE(
      SparseVoVerdictReasons(SparseRun(300, 0.0016, true), SparseVoOptions{}, kRadius).empty());
}

}  // namespace
}  // namespace pipescope
