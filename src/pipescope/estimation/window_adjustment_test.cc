#include "pipescope/estimation/window_adjustment.h"

#include <gtest/gtest.h>

#include "pipescope/estimation/estimation_testing.h"

namespace pipescope {
namespace {

constexpr double kRadius = 0.07666;

// Eight key frames with pitch and yaw wobble and drift across the pipe; the first two are held
// at the truth, the others start at the 1-DOF guess (start rotation, on the first one's line)
// and must come back to the truth.
TEST(AdjustWindow, RecoversWobblingPosesThroughTheCylinder) {
  const Camera camera = SteelSixInchCamera();
  std::vector<Eigen::Isometry3d> truth;
  for (int a = 0; a < 8; ++a) {
    Eigen::Isometry3d pose = WallLookingPose({0.001 * std::sin(a), 0.002 - 0.0003 * a, 0.01 * a});
    pose.linear() = Eigen::AngleAxisd(0.008 * std::sin(1.3 * a), Eigen::Vector3d::UnitX()) *
                    Eigen::AngleAxisd(0.005 * std::cos(a), Eigen::Vector3d::UnitY()) *
                    pose.linear();
    truth.push_back(pose);
  }
  std::vector<Eigen::Vector3d> points;
  for (int a = 0; a < 8; ++a) {
    for (const Eigen::Vector3d& p : WallPointsSeenFrom(camera, truth[a], kRadius, 60, 40 + a)) {
      points.push_back(p);
    }
  }
  std::vector<WindowKeyFrame> window(8);
  for (int a = 0; a < 8; ++a) {
    window[a].fixed = a < 2;
    window[a].pose = a < 2 ? truth[a] : truth[0];
    window[a].pose.translation().z() = truth[a].translation().z() + 0.0005;
    if (a < 2) window[a].pose = truth[a];
    window[a].keypoints = ObservedKeypoints(camera, truth[a], points);
  }
  WindowAdjustmentOptions options;
  options.max_iterations = 50;
  const WindowAdjustmentSummary summary = AdjustWindow(camera, kRadius, options, &window);
  EXPECT_GT(summary.initial_rms_px, 1.0);
  EXPECT_LT(summary.final_rms_px, 1e-4);
  for (int a = 2; a < 8; ++a) {
    EXPECT_LT((window[a].pose.translation() - truth[a].translation()).norm(), 1e-6) << a;
    EXPECT_LT(Eigen::AngleAxisd(window[a].pose.linear() * truth[a].linear().transpose()).angle(),
              1e-5)
        << a;
  }
}

// No key frame fixed: the gauge prior holds the first one's travel and roll; with
// hold_first_cross_section its position across the pipe also stays where it was put (the
// measured start), even when the reprojections would move it.
TEST(AdjustWindow, HoldsTheFirstKeyFramesCrossSectionWhenAsked) {
  const Camera camera = SteelSixInchCamera();
  std::vector<Eigen::Isometry3d> truth;
  for (int a = 0; a < 6; ++a) truth.push_back(WallLookingPose({0.0, 0.001 - 0.0002 * a, 0.01 * a}));
  std::vector<Eigen::Vector3d> points;
  for (int a = 0; a < 6; ++a) {
    for (const Eigen::Vector3d& p : WallPointsSeenFrom(camera, truth[a], kRadius, 60, 70 + a)) {
      points.push_back(p);
    }
  }
  std::vector<WindowKeyFrame> window(6);
  for (int a = 0; a < 6; ++a) {
    window[a].pose = truth[a];
    window[a].pose.translation().y() += 0.0008;  // everyone moved towards the wall
    window[a].keypoints = ObservedKeypoints(camera, truth[a], points);
  }
  WindowAdjustmentOptions options;
  options.max_iterations = 50;
  options.hold_first_cross_section = true;
  const Eigen::Vector3d held = window[0].pose.translation();
  std::vector<WindowKeyFrame> free_window = window;
  AdjustWindow(camera, kRadius, options, &window);
  EXPECT_LT((window[0].pose.translation() - held).head<2>().norm(), 1e-12);
  // Free, the 70-degree lens sees the wall's curvature well enough to come back to the truth.
  options.hold_first_cross_section = false;
  AdjustWindow(camera, kRadius, options, &free_window);
  EXPECT_LT((free_window[0].pose.translation() - truth[0].translation()).norm(), 1e-5);
}

}  // namespace
}  // namespace pipescope
