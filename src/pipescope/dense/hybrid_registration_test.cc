#include "pipescope/dense/hybrid_registration.h"

#include <gtest/gtest.h>

#include <cmath>

#include "pipescope/dense/testing.h"

namespace pipescope {
namespace {

TEST(HybridRegistration, RecoversSubPixelShifts) {
  int seed = 40;
  for (const FullSearchCost cost :
       {FullSearchCost::kSad, FullSearchCost::kSsd, FullSearchCost::kZncc}) {
    for (const cv::Point2d shift : {cv::Point2d(12.38, -3.71), cv::Point2d(-25.55, 7.49),
                                    cv::Point2d(0.62, 0.0), cv::Point2d(-4.0, 9.0)}) {
      const RegistrationPair pair = MakeRegistrationPair({256, 192}, shift, 0.0, 1.0, ++seed);
      HybridOptions options;
      options.full_search.cost = cost;
      const HybridResult result = RegisterHybrid(pair.reference, pair.next, options);
      EXPECT_TRUE(result.refined);
      EXPECT_FALSE(result.still);
      EXPECT_LE(Distance(result.shift, shift), 0.05) << shift << result.shift;
      EXPECT_LE(Distance(cv::Point2d(result.integer_shift), shift), 0.71);
      EXPECT_GT(result.iterations, 0);
    }
  }
}

TEST(HybridRegistration, StillPairIsExactlyZero) {
  // The same wall, independent noise: iterative refinement alone never returns exactly zero
  // (000 §4.2.3), the hybrid does.
  int nonzero_lucas_kanade = 0;
  for (int seed = 1; seed <= 10; ++seed) {
    for (const cv::Size size : {cv::Size(256, 192), cv::Size(160, 120)}) {
      const RegistrationPair pair = MakeRegistrationPair(size, {0.0, 0.0}, 0.0, 2.0, seed);
      const HybridResult result = RegisterHybrid(pair.reference, pair.next);
      EXPECT_TRUE(result.still) << seed;
      EXPECT_EQ(result.shift.x, 0.0);
      EXPECT_EQ(result.shift.y, 0.0);
      const LucasKanadeResult lk = RegisterLucasKanade(pair.reference, pair.next);
      if (lk.shift.x != 0.0 || lk.shift.y != 0.0) ++nonzero_lucas_kanade;
    }
  }
  EXPECT_EQ(nonzero_lucas_kanade, 20);
}

TEST(HybridRegistration, SlowMotionIsNotStill) {
  int seed = 60;
  for (const cv::Point2d shift :
       {cv::Point2d(0.3, 0.0), cv::Point2d(0.1, -0.05), cv::Point2d(0.0, -0.45)}) {
    const RegistrationPair pair = MakeRegistrationPair({256, 192}, shift, 0.0, 1.0, ++seed);
    const HybridResult result = RegisterHybrid(pair.reference, pair.next);
    EXPECT_EQ(result.integer_shift, cv::Point(0, 0));
    EXPECT_FALSE(result.still) << shift;
    EXPECT_LE(Distance(result.shift, shift), 0.05) << shift << result.shift;
  }
}

TEST(HybridRegistration, StillThresholdsCanBeTurnedOff) {
  const RegistrationPair pair = MakeRegistrationPair({160, 120}, {0.0, 0.0}, 0.0, 2.0, 3);
  HybridOptions options;
  options.still_shift_px = 0.0;
  options.still_chi2 = 0.0;
  const HybridResult result = RegisterHybrid(pair.reference, pair.next, options);
  EXPECT_FALSE(result.still);
  EXPECT_TRUE(result.refined);
  EXPECT_LT(Distance(result.shift, {0.0, 0.0}), 0.05);
  EXPECT_NE(result.shift, cv::Point2d(0.0, 0.0));
}

}  // namespace
}  // namespace pipescope
