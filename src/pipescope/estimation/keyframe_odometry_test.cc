// KeyframeOdometry on synthetic tracks: key frames down a straight pipe whose features are exact
// projections of points on the wall, with the relative poses a perfect five-point step would
// give. The odometry must recover the metric path from the radius alone.
#include "pipescope/estimation/keyframe_odometry.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>
#include <vector>

#include "pipescope/estimation/straight_window_testing.h"

namespace pipescope {
namespace {

constexpr double kRadius = 0.2;
constexpr double kStep = 0.02;         // metres a key frame
constexpr int kFramesPerKeyframe = 2;  // frame indices advance by this

class KeyframeOdometryTest : public testing::Test {
 protected:
  KeyframeOdometryTest() : camera_(FisheyeTestCamera()) {
    std::mt19937 random(7);
    std::uniform_real_distribution<double> angle(-M_PI, M_PI);
    std::uniform_real_distribution<double> along(-0.2, 2.5);
    for (int i = 0; i < 4000; ++i) {
      const double phi = angle(random);
      wall_points_.emplace_back(kRadius * std::cos(phi), kRadius * std::sin(phi), along(random));
    }
    options_.window.radius_m = kRadius;
  }

  // Key frame k as the tracker would hand it over: every wall point between 3 cm and 60 cm
  // ahead that projects within 70 degrees of the optical axis, with its exact pixel and
  // bearing; the relative pose from key frame k - 1 up to scale. `track_offset` renames the
  // tracks (a tracking reset starts new ones).
  TrackedKeyframe Keyframe(int k, long track_offset = 0, bool has_previous = true) const {
    TrackedKeyframe keyframe;
    keyframe.frame_index = kFramesPerKeyframe * k;
    const Eigen::Isometry3d cam_from_world = WobblingCamFromWorld(station_(k), kStep);
    const double ahead_min = kStep * station_(k) + 0.03, ahead_max = kStep * station_(k) + 0.6;
    for (std::size_t i = 0; i < wall_points_.size(); ++i) {
      const Eigen::Vector3d& point = wall_points_[i];
      if (point.z() < ahead_min || point.z() > ahead_max) continue;
      const Eigen::Vector3d point_cam = cam_from_world * point;
      if (point_cam.normalized().z() < std::cos(70.0 * M_PI / 180.0)) continue;
      Eigen::Vector2d pixel;
      if (camera_.Project(point_cam, &pixel) != ProjectionStatus::kValid) continue;
      keyframe.features.push_back(
          {static_cast<long>(i) + track_offset,
           cv::Point2f(static_cast<float>(pixel.x()), static_cast<float>(pixel.y())),
           point_cam.normalized()});
    }
    if (k > 0 && has_previous) {
      const Eigen::Isometry3d this_from_previous =
          cam_from_world * WobblingCamFromWorld(station_(k - 1), kStep).inverse();
      keyframe.has_previous = true;
      keyframe.relative_pose.success = true;
      keyframe.relative_pose.rotation = this_from_previous.linear();
      // Standing still, the five-point translation is noise: some sideways direction.
      keyframe.relative_pose.translation = this_from_previous.translation().norm() > 1e-9
                                               ? this_from_previous.translation().normalized()
                                               : Eigen::Vector3d(0.6, 0.8, 0.0);
    }
    return keyframe;
  }

  // Key frame k's true pose in the first key frame's camera frame (the odometry's world).
  Eigen::Isometry3d TrueWorldFromCam(int k) const {
    return WobblingCamFromWorld(station_(0), kStep) *
           WobblingCamFromWorld(station_(k), kStep).inverse();
  }

  static KeyframeSection Straight(int k, int count) {
    return {k, 0, PipeViewClass::kStraight, 0, k == count - 1};
  }

  Camera camera_;
  std::vector<Eigen::Vector3d> wall_points_;
  KeyframeOdometryOptions options_;
  // Where key frame k stands, in steps of kStep down the pipe (the camera always looks down it).
  std::function<int(int)> station_ = [](int k) { return k; };
};

TEST_F(KeyframeOdometryTest, RecoversTheMetricPathFromTheRadius) {
  constexpr int kCount = 60;
  KeyframeOdometry odometry(camera_, options_);
  for (int k = 0; k < kCount; ++k) odometry.Add(Keyframe(k), Straight(k, kCount));
  ASSERT_EQ(odometry.KeyframeCount(), kCount);
  double max_error = 0.0;
  for (int k = 0; k < kCount; ++k) {
    max_error = std::max(
        max_error,
        (odometry.WorldFromCam(k).translation() - TrueWorldFromCam(k).translation()).norm());
  }
  // 1.18 m of travel, no drift to speak of with exact tracks: the scale comes from the radius.
  EXPECT_LT(max_error, 0.002);
  const double travelled =
      (odometry.WorldFromCam(kCount - 1).translation() - odometry.WorldFromCam(0).translation())
          .norm();
  EXPECT_NEAR(travelled, kStep * (kCount - 1), 0.001 * kStep * (kCount - 1));
  // Every step's length came from the points put on the wall, none from the prediction.
  for (int k = 1; k < kCount; ++k) EXPECT_GE(odometry.StepRecord(k).points_used, 20) << k;
  // The windows ran with the cylinder and were applied.
  int applied = 0;
  for (const OdometryWindowRecord& window : odometry.windows()) {
    EXPECT_TRUE(window.cylinder);
    if (window.rejection.empty()) ++applied;
  }
  // Every 20 key frames (window_interval), each one applied.
  EXPECT_EQ(odometry.windows().size(), static_cast<std::size_t>(kCount / options_.window_interval));
  EXPECT_EQ(applied, static_cast<int>(odometry.windows().size()));
  // The triangulated points lie on the wall of the true pipe.
  const Eigen::Isometry3d world_from_first = WobblingCamFromWorld(0, kStep).inverse();
  const std::vector<SparsePoint> points = odometry.Points();
  ASSERT_GT(points.size(), 200u);
  std::vector<double> wall_errors;
  for (const SparsePoint& point : points) {
    const Eigen::Vector3d in_pipe = world_from_first * point.position;
    wall_errors.push_back(std::abs(in_pipe.head<2>().norm() - kRadius));
  }
  std::sort(wall_errors.begin(), wall_errors.end());
  EXPECT_LT(wall_errors[wall_errors.size() / 2], 0.001);
}

// The section's last key frame runs a window over it, unless it holds fewer than
// min_window_keyframes.
TEST_F(KeyframeOdometryTest, ASectionEndsWithAWindowWhenItIsLongEnough) {
  options_.window_interval = 100000;
  options_.min_window_keyframes = 12;
  for (const int count : {11, 12}) {
    KeyframeOdometry odometry(camera_, options_);
    for (int k = 0; k < count; ++k) odometry.Add(Keyframe(k), Straight(k, count));
    EXPECT_EQ(odometry.windows().size(), count >= 12 ? 1u : 0u) << count;
  }
}

TEST_F(KeyframeOdometryTest, WithoutWindowsEachStepLengthComesFromTheRadius) {
  // No window adjustment: every step length is the scale that puts the step's two-view points
  // on the wall of a cylinder fitted to them (001 eq. 4-6; cylinder_scale.h), nothing else.
  options_.window_interval = 100000;
  options_.min_window_keyframes = 100000;  // nor one at the section's end
  options_.fit_axis_per_step = true;
  constexpr int kCount = 40;
  KeyframeOdometry odometry(camera_, options_);
  for (int k = 0; k < kCount; ++k) odometry.Add(Keyframe(k), Straight(k, kCount));
  EXPECT_TRUE(odometry.windows().empty());
  double max_step_error = 0.0;
  for (int k = 1; k < kCount; ++k) {
    const double step =
        (odometry.WorldFromCam(k).translation() - odometry.WorldFromCam(k - 1).translation())
            .norm();
    const double true_step =
        (TrueWorldFromCam(k).translation() - TrueWorldFromCam(k - 1).translation()).norm();
    max_step_error = std::max(max_step_error, std::abs(step / true_step - 1.0));
  }
  EXPECT_LT(max_step_error, 1e-4);
}

TEST_F(KeyframeOdometryTest, ATranslationOffTheRecentDirectionIsReplacedByTheRecentMotion) {
  constexpr int kCount = 25;
  KeyframeOdometry odometry(camera_, options_);
  for (int k = 0; k < kCount; ++k) {
    TrackedKeyframe keyframe = Keyframe(k);
    // RANSAC traded the step for a sideways translation.
    if (k == 15) keyframe.relative_pose.translation = Eigen::Vector3d::UnitX();
    odometry.Add(std::move(keyframe), Straight(k, kCount));
  }
  EXPECT_TRUE(odometry.StepRecord(15).direction_rejected);
  EXPECT_FALSE(odometry.StepRecord(14).direction_rejected);
  // The step continued the recent motion: within millimetres of the truth.
  EXPECT_LT((odometry.WorldFromCam(15).translation() - TrueWorldFromCam(15).translation()).norm(),
            0.003);
}

TEST_F(KeyframeOdometryTest, ATrackingResetContinuesAtTheRecentSpeed) {
  constexpr int kCount = 30;
  KeyframeOdometry odometry(camera_, options_);
  for (int k = 0; k < kCount; ++k) {
    // From key frame 20 on the tracks are new: nothing links 20 to 19.
    const bool reset = k >= 20;
    odometry.Add(Keyframe(k, reset ? 1000000 : 0, k != 20), Straight(k, kCount));
  }
  const double step =
      (odometry.WorldFromCam(20).translation() - odometry.WorldFromCam(19).translation()).norm();
  EXPECT_NEAR(step, kStep, 0.05 * kStep);
  EXPECT_EQ(odometry.StepRecord(20).points_used, 0);
  // After the reset the radius fixes the steps again.
  EXPECT_GE(odometry.StepRecord(25).points_used, 20);
  EXPECT_NEAR(
      (odometry.WorldFromCam(kCount - 1).translation() - odometry.WorldFromCam(0).translation())
          .norm(),
      kStep * (kCount - 1), 0.01 * kStep * (kCount - 1));
}

TEST_F(KeyframeOdometryTest, ACrawlerThatReversesIsFollowedBack) {
  // Down the pipe for 20 key frames, then back up it, looking down it all the while: the
  // steps' direction flips, which is the same line, not a wrong relative pose.
  station_ = [](int k) { return k < 20 ? k : 38 - k; };
  constexpr int kCount = 36;
  KeyframeOdometry odometry(camera_, options_);
  for (int k = 0; k < kCount; ++k) odometry.Add(Keyframe(k), Straight(k, kCount));
  for (int k = 1; k < kCount; ++k) EXPECT_FALSE(odometry.StepRecord(k).direction_rejected) << k;
  for (int k : {19, 25, kCount - 1}) {
    EXPECT_LT((odometry.WorldFromCam(k).translation() - TrueWorldFromCam(k).translation()).norm(),
              0.003)
        << k;
  }
}

TEST_F(KeyframeOdometryTest, ACrawlerThatStandsStillKeepsItsPlace) {
  // Key frames 15-19 stand where 14 stood; their relative poses' translations are noise.
  station_ = [](int k) { return k < 15 ? k : (k < 20 ? 14 : k - 5); };
  constexpr int kCount = 30;
  KeyframeOdometry odometry(camera_, options_);
  for (int k = 0; k < kCount; ++k) odometry.Add(Keyframe(k), Straight(k, kCount));
  for (int k = 1; k < kCount; ++k) {
    const bool still = k >= 15 && k < 20;
    EXPECT_EQ(odometry.StepRecord(k).stationary, still) << k;
    EXPECT_FALSE(odometry.StepRecord(k).direction_rejected) << k;
  }
  for (int k = 15; k < 20; ++k) {
    EXPECT_LT(
        (odometry.WorldFromCam(k).translation() - odometry.WorldFromCam(14).translation()).norm(),
        0.001)
        << k;
  }
  EXPECT_LT(
      (odometry.WorldFromCam(kCount - 1).translation() - TrueWorldFromCam(kCount - 1).translation())
          .norm(),
      0.003);
}

}  // namespace
}  // namespace pipescope
