#include "pipescope/pipeline/window_confirmation.h"

#include <gtest/gtest.h>

namespace pipescope {
namespace {

OdometryWindowRecord Window(bool straight, const std::string& rejection, int section = 0) {
  OdometryWindowRecord window;
  window.section = section;
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
  ASSERT_EQ(reasons.size(), 2u);  // the run's, then its one section's
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

// The route's last section fails while the long sections before it hold: the run as a whole is
// far under the 50 % limit, but that section's length is not confirmed.
TEST(WindowConfirmation, OneSectionMostlyRejectedIsNamed) {
  std::vector<OdometryWindowRecord> windows;
  for (int i = 0; i < 78; ++i) windows.push_back(Window(true, i < 2 ? "image rms" : "", 2));
  for (int i = 0; i < 26; ++i) {
    OdometryWindowRecord window = Window(true, i % 2 == 0 && i < 22 ? "cylinder rms" : "", 8);
    window.first_keyframe = 900 + 10 * i;
    window.last_keyframe = window.first_keyframe + 19;
    windows.push_back(window);
  }
  const std::vector<std::string> reasons = WindowConfirmationReasons(windows, 500);
  ASSERT_EQ(reasons.size(), 1u);
  EXPECT_NE(reasons[0].find("straight section 8 (key frames 900-1169): 11 of 26 window"),
            std::string::npos)
      << reasons[0];
  EXPECT_NE(reasons[0].find("cylinder rms: 11"), std::string::npos);
}

TEST(WindowConfirmation, ASectionWithFewWindowsIsNotJudgedByItsShare) {
  // 2 of 3 rejected in section 1: too few windows to tell a failing section from bad luck;
  // the run's share (2 of 13) holds.
  std::vector<OdometryWindowRecord> windows(10, Window(true, "", 0));
  windows.push_back(Window(true, "image rms", 1));
  windows.push_back(Window(true, "image rms", 1));
  windows.push_back(Window(true, "", 1));
  EXPECT_TRUE(WindowConfirmationReasons(windows, 100).empty());
  windows.push_back(Window(true, "", 1));  // 2 of 4: over a quarter
  EXPECT_EQ(WindowConfirmationReasons(windows, 100).size(), 1u);
  WindowConfirmationOptions lenient;
  lenient.max_rejected_section_share = 0.5;
  EXPECT_TRUE(WindowConfirmationReasons(windows, 100, lenient).empty());
}

// A map run: only its straight sections may owe a window, and the options' limits are used.
TEST(WindowConfirmation, AMapRunCountsItsLongestStraightSection) {
  FisheyeMappingResult result;
  result.sections = {{0, 8, PipeViewClass::kStraight},
                     {9, 40, PipeViewClass::kTIntersection},
                     {41, 49, PipeViewClass::kStraight}};
  FisheyeMappingOptions options;
  options.odometry.min_window_keyframes = 10;
  EXPECT_TRUE(WindowConfirmationReasons(result, options).empty());  // 9 key frames at most
  result.sections.push_back({50, 59, PipeViewClass::kStraight});
  EXPECT_EQ(WindowConfirmationReasons(result, options).size(), 1u);  // 10: one was due
  result.windows = {Window(true, "image rms"), Window(true, "")};
  EXPECT_TRUE(WindowConfirmationReasons(result, options).empty());
  options.max_rejected_window_share = 0.25;
  EXPECT_EQ(WindowConfirmationReasons(result, options).size(), 1u);
  // A section's share comes from the map's options too.
  options.max_rejected_window_share = 0.5;
  result.windows = {Window(true, "image rms"), Window(true, ""), Window(true, ""),
                    Window(true, "")};
  EXPECT_TRUE(WindowConfirmationReasons(result, options).empty());
  options.max_rejected_section_window_share = 0.2;
  EXPECT_EQ(WindowConfirmationReasons(result, options).size(), 1u);
}

}  // namespace
}  // namespace pipescope
