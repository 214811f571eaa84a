#include "pipescope/estimation/predicted_stretch_bridging.h"

#include <gtest/gtest.h>

#include <cmath>

namespace pipescope {
namespace {

// A camera moving along z at 10 mm a frame, turning 1 degree a frame about z.
Trajectory SteadyRun(int frames) {
  Trajectory trajectory;
  for (int i = 0; i < frames; ++i) {
    StampedPose pose;
    pose.timestamp = i / 30.0;
    pose.position = Eigen::Vector3d(0, 0, 0.01 * i);
    pose.rotation =
        Eigen::Quaterniond(Eigen::AngleAxisd(i * M_PI / 180.0, Eigen::Vector3d::UnitZ()));
    trajectory.push_back(pose);
  }
  return trajectory;
}

TEST(BridgePredictedStretches, EnclosedStretchIsInterpolatedBetweenItsMeasuredNeighbours) {
  const Trajectory truth = SteadyRun(10);
  Trajectory estimate = truth;
  std::vector<FrameMeasurement> frames(10);
  // Frames 4-6 failed and were predicted 5 mm too far each; frame 7 was registered to the key
  // frame of frame 3 again.
  for (int k = 4; k <= 6; ++k) {
    frames[k].predicted = true;
    estimate[k].position.z() += 0.005 * (k - 3);
    estimate[k].rotation = Eigen::Quaterniond::Identity();
  }
  const std::vector<std::size_t> bridged = BridgePredictedStretches(frames, &estimate);
  EXPECT_EQ(bridged, (std::vector<std::size_t>{4, 5, 6}));
  for (int k = 0; k < 10; ++k) {
    EXPECT_NEAR((estimate[k].position - truth[k].position).norm(), 0.0, 1e-12) << k;
    EXPECT_NEAR(estimate[k].rotation.angularDistance(truth[k].rotation), 0.0, 1e-9) << k;
  }
}

TEST(BridgePredictedStretches, LeavesStretchesAtTheEndsAndThoseCarriedByAKeyFrame) {
  Trajectory estimate = SteadyRun(12);
  const Trajectory before = estimate;
  std::vector<FrameMeasurement> frames(12);
  frames[0].predicted = true;                          // at the start: nothing before it
  frames[4].predicted = frames[5].predicted = true;    // a predicted frame became key:
  frames[5].became_key = true;                         // later poses rest on it
  frames[10].predicted = frames[11].predicted = true;  // at the end: nothing after it
  for (int k : {0, 4, 5, 10, 11}) estimate[k].position.x() += 0.003;
  EXPECT_TRUE(BridgePredictedStretches(frames, &estimate).empty());
  for (int k : {0, 4, 5, 10, 11}) {
    EXPECT_DOUBLE_EQ(estimate[k].position.x(), before[k].position.x() + 0.003);
  }
  std::vector<FrameMeasurement> wrong_size(3);
  EXPECT_THROW(BridgePredictedStretches(wrong_size, &estimate), std::invalid_argument);
}

}  // namespace
}  // namespace pipescope
