#include "pipescope/pipeline/window_confirmation.h"

#include <gtest/gtest.h>

namespace pipescope {
namespace {

OdometryWindowRecord Window(bool straight, const std::string& rejection) {
  OdometryWindowRecord window;
  window.straight = straight;
  window.cylinder = straight;
  window.rejection = rejection;
  return window;
}

TEST(WindowConfirmation, HalfTheWindowsRejectedStillConfirms) {
  const std::vector<OdometryWindowRecord> windows = {Window(true, ""), Window(true, "image rms")};
  EXPECT_TRUE(WindowConfirmationReasons(windows, 100).empty());
}

TEST(WindowConfirmation, MostWindowsRejectedSaysHowManyAndWhy) {
  const std::vector<OdometryWindowRecord> windows = {Window(true, "cylinder rms"),
                                                     Window(true, "cylinder rms"),
                                                     Window(true, "image rms"), Window(true, "")};
  const std::vector<std::string> reasons = WindowConfirmationReasons(windows, 100);
  ASSERT_EQ(reasons.size(), 1u);
  EXPECT_NE(reasons[0].find("3 of 4 window adjustments were rejected"), std::string::npos);
  EXPECT_NE(reasons[0].find("cylinder rms: 2"), std::string::npos);
  EXPECT_NE(reasons[0].find("image rms: 1"), std::string::npos);
}

TEST(WindowConfirmation, IntersectionWindowsDoNotCount) {
  // T-intersection windows (no cylinder) are rejected more often and do not set the scale.
  const std::vector<OdometryWindowRecord> windows = {Window(false, "path length"),
                                                     Window(false, "image rms"), Window(true, "")};
  EXPECT_TRUE(WindowConfirmationReasons(windows, 100).empty());
}

TEST(WindowConfirmation, NoWindowIsWrongOnlyWhereOneWasDue) {
  EXPECT_TRUE(WindowConfirmationReasons({}, 9).empty());
  const std::vector<std::string> reasons = WindowConfirmationReasons({}, 10);
  ASSERT_EQ(reasons.size(), 1u);
  EXPECT_NE(reasons[0].find("no window adjustment ran in a straight section of 10 key frames"),
            std::string::npos);
}

TEST(WindowConfirmation, TheLimitIsSettable) {
  const std::vector<OdometryWindowRecord> windows = {Window(true, "image rms"), Window(true, "")};
  WindowConfirmationOptions strict;
  strict.max_rejected_share = 0.25;
  EXPECT_EQ(WindowConfirmationReasons(windows, 100, strict).size(), 1u);
}

// A map run: only its straight sections may owe a window, and the options' limits are used.
TEST(WindowConfirmation, AMapRunCountsItsLongestStraightSection) {
  FisheyeMappingResult result;
  result.sections = {{0, 8, PipeViewClass::kStraight},
                     {9, 40, PipeViewClass::kTIntersection},
                     {41, 49, PipeViewClass::kStraight}};
  FisheyeMappingOptions options;
  options.odometry.window_interval = 10;
  EXPECT_TRUE(WindowConfirmationReasons(result, options).empty());  // 9 key frames at most
  result.sections.push_back({50, 59, PipeViewClass::kStraight});
  EXPECT_EQ(WindowConfirmationReasons(result, options).size(), 1u);  // 10: one was due
  result.windows = {Window(true, "image rms"), Window(true, "")};
  EXPECT_TRUE(WindowConfirmationReasons(result, options).empty());
  options.max_rejected_window_share = 0.25;
  EXPECT_EQ(WindowConfirmationReasons(result, options).size(), 1u);
}

}  // namespace
}  // namespace pipescope
