#include "pipescope/report/run_quality.h"

#include <gtest/gtest.h>

namespace pipescope {
namespace {

constexpr FrameState M = FrameState::kMeasured;
constexpr FrameState P = FrameState::kPredicted;
constexpr FrameState N = FrameState::kNotLocalised;

std::vector<FrameState> Measured(int count) { return std::vector<FrameState>(count, M); }

TEST(RunQuality, AFewScatteredPredictionsAreReliable) {
  std::vector<FrameState> states = Measured(100);
  states[10] = states[50] = states[90] = P;
  states[20] = N;
  const RunQuality quality = AssessRunQuality(states);
  EXPECT_TRUE(quality.reliable);
  EXPECT_EQ(quality.measured, 96);
  EXPECT_EQ(quality.predicted, 3);
  EXPECT_EQ(quality.not_localised, 1);
  EXPECT_EQ(quality.longest_predicted_stretch, 1);
  EXPECT_EQ(quality.predicted_frames, (std::vector<int>{10, 50, 90}));
  EXPECT_EQ(RunQualityJson(quality)["verdict"], "reliable");
}

TEST(RunQuality, AStretchOfPredictionsIsUnreliableAndSaysWhere) {
  std::vector<FrameState> states = Measured(200);
  // Six predicted frames in a row, an unreadable one among them: 1.5 % of the frames, but one
  // guess carried over 7 frames.
  for (int i = 40; i < 47; ++i) states[i] = P;
  states[43] = N;
  const RunQuality quality = AssessRunQuality(states);
  EXPECT_FALSE(quality.reliable);
  EXPECT_EQ(quality.longest_predicted_stretch, 6);
  EXPECT_EQ(quality.longest_stretch_first_frame, 40);
  ASSERT_EQ(quality.reasons.size(), 1u);
  EXPECT_NE(quality.reasons[0].find("from frame 40"), std::string::npos) << quality.reasons[0];
  EXPECT_NE(RunQualitySummary(quality).find("UNRELIABLE"), std::string::npos);
}

// A slow crawler's key frames lie 8 frames apart: one rejected key-frame step predicts 8 frames,
// which is one step, not a stretch; five steps in a row still are.
TEST(RunQuality, KeyframeSpacingScalesTheStretchLimit) {
  const std::vector<int> every_eighth = {0, 8, 16, 23, 31, 40, 48};  // spacings 8, 8, 7, 8, 9, 8
  const RunQualityLimits limits = KeyframeQualityLimits(every_eighth);
  EXPECT_EQ(limits.max_predicted_stretch, 5 * 8);
  EXPECT_EQ(limits.max_predicted_share, RunQualityLimits().max_predicted_share);

  std::vector<FrameState> states = Measured(2000);  // shares stay under the 5 % limit
  for (int i = 101; i <= 108; ++i) states[i] = P;
  EXPECT_FALSE(AssessRunQuality(states).reliable);  // 8 frames against the per-frame limit of 5
  EXPECT_TRUE(AssessRunQuality(states, limits).reliable);
  for (int i = 101; i <= 148; ++i) states[i] = P;  // six steps
  const RunQuality six_steps = AssessRunQuality(states, limits);
  EXPECT_FALSE(six_steps.reliable);
  ASSERT_EQ(six_steps.reasons.size(), 1u);
  EXPECT_NE(six_steps.reasons[0].find("48 frames in a row"), std::string::npos);

  // Every frame a key frame (1 cm a frame), or no spacing at all: the per-frame limit.
  EXPECT_EQ(KeyframeQualityLimits({0, 1, 2, 3}).max_predicted_stretch, 5);
  EXPECT_EQ(KeyframeQualityLimits({0}).max_predicted_stretch, 5);
}

TEST(RunQuality, SharesAboveTheLimitsAreUnreliable) {
  std::vector<FrameState> states = Measured(100);
  for (int i = 0; i < 100; i += 10) states[i] = P;  // 10 %, never two in a row
  for (int i = 5; i < 100; i += 10) states[i] = N;  // 10 %
  const RunQuality quality = AssessRunQuality(states);
  EXPECT_FALSE(quality.reliable);
  EXPECT_EQ(quality.reasons.size(), 2u);
  EXPECT_EQ(RunQualityJson(quality)["verdict"], "unreliable");
  EXPECT_DOUBLE_EQ(RunQualityJson(quality)["predicted_share"].get<double>(), 0.1);
  // At the limits exactly, still reliable.
  std::vector<FrameState> at_limit = Measured(100);
  for (int i = 0; i < 5; ++i) at_limit[i * 20] = P;
  EXPECT_TRUE(AssessRunQuality(at_limit).reliable);
  EXPECT_FALSE(AssessRunQuality({M, P, P}).reliable);  // fewer than 2 measured
}

// What a reader of run.json (odometry's fallback) counts against the distances along the pipe.
TEST(RunQuality, AlongPipeReasonsLeaveOutThePositionReasons) {
  RunQuality quality = AssessRunQuality(Measured(10));
  quality.reliable = false;
  quality.reasons = {"a turn", "thin tracks", "another turn"};
  quality.position_reasons = {"a turn", "another turn"};
  EXPECT_EQ(AlongPipeReasons(RunQualityJson(quality)), std::vector<std::string>{"thin tracks"});
  quality.reasons = quality.position_reasons;
  EXPECT_TRUE(AlongPipeReasons(RunQualityJson(quality)).empty());
  // A block without position_reasons (written before they existed): every reason counts.
  nlohmann::json old_block = RunQualityJson(quality);
  old_block.erase("position_reasons");
  EXPECT_EQ(AlongPipeReasons(old_block).size(), 2u);
}

}  // namespace
}  // namespace pipescope
