#include "pipescope/estimation/window_adjustment.h"

#include <gtest/gtest.h>

#include <cstdio>

#include "pipescope/estimation/estimation_testing.h"

namespace pipescope {
namespace {

constexpr double kRadius = 0.07666;

// 60 wall points seen from each pose (seeds seed, seed + 1, ...).
std::vector<Eigen::Vector3d> PointsSeenFromEach(const Camera& camera,
                                                const std::vector<Eigen::Isometry3d>& poses,
                                                unsigned seed) {
  std::vector<Eigen::Vector3d> points;
  for (std::size_t a = 0; a < poses.size(); ++a) {
    for (const Eigen::Vector3d& p :
         WallPointsSeenFrom(camera, poses[a], kRadius, 60, seed + static_cast<unsigned>(a))) {
      points.push_back(p);
    }
  }
  return points;
}

// Key frames at the true poses seeing `points` exactly; the first is held.
std::vector<WindowKeyFrame> ExactWindowHoldingTheFirst(const Camera& camera,
                                                       const std::vector<Eigen::Isometry3d>& truth,
                                                       const std::vector<Eigen::Vector3d>& points) {
  std::vector<WindowKeyFrame> window(truth.size());
  for (std::size_t a = 0; a < truth.size(); ++a) {
    window[a].pose = truth[a];
    window[a].fixed = a == 0;
    window[a].keypoints = ObservedKeypoints(camera, truth[a], points);
  }
  return window;
}

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
  const std::vector<Eigen::Vector3d> points = PointsSeenFromEach(camera, truth, 40);
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
  const std::vector<Eigen::Vector3d> points = PointsSeenFromEach(camera, truth, 70);
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

// The cross-section smoothness prior: key frames whose true positions step 0.2 mm across the pipe
// each, all seen exactly. With a loose prior the adjustment keeps the truth (the prior does not
// bias an exact solution beyond its weight); with a stiff one the steps shrink towards zero,
// which only the prior can do (the reprojections alone are exact at the truth).
TEST(AdjustWindow, CrossSectionPriorPullsConsecutiveKeyFramesTogether) {
  const Camera camera = SteelSixInchCamera();
  std::vector<Eigen::Isometry3d> truth;
  for (int a = 0; a < 6; ++a) truth.push_back(WallLookingPose({0.0002 * a, 0.0, 0.01 * a}));
  const std::vector<Eigen::Vector3d> points = PointsSeenFromEach(camera, truth, 90);
  const std::vector<WindowKeyFrame> window = ExactWindowHoldingTheFirst(camera, truth, points);
  auto last_step_across = [](const std::vector<WindowKeyFrame>& adjusted) {
    return (adjusted[5].pose.translation() - adjusted[4].pose.translation()).head<2>().norm();
  };
  WindowAdjustmentOptions options;
  options.max_iterations = 50;
  options.cross_section_step_sigma_m = 1.0;
  std::vector<WindowKeyFrame> loose = window;
  AdjustWindow(camera, kRadius, options, &loose);
  EXPECT_NEAR(last_step_across(loose), 0.0002, 1e-6);
  options.cross_section_step_sigma_m = 1e-8;
  std::vector<WindowKeyFrame> stiff = window;
  AdjustWindow(camera, kRadius, options, &stiff);
  EXPECT_LT(last_step_across(stiff), 0.00002);
}

// Six key frames 10 mm apart, all truly 1 mm nearer the wall than an anchor at the axis, seen
// exactly, the first held.
std::vector<Eigen::Isometry3d> OneMillimetreNearerTheWall() {
  std::vector<Eigen::Isometry3d> truth;
  for (int a = 0; a < 6; ++a) truth.push_back(WallLookingPose({0.0, 0.001, 0.01 * a}));
  return truth;
}

// The cross-section anchor: key frames truly 1 mm nearer the wall than the anchor, seen exactly.
// A loose anchor keeps the truth; a stiff one puts every free key frame's C_X, C_Y on the anchor
// (only the prior can: the reprojections alone are exact at the truth) and leaves the held one
// alone.
TEST(AdjustWindow, CrossSectionAnchorPullsFreeKeyFramesToTheMeasuredStart) {
  const Camera camera = SteelSixInchCamera();
  const std::vector<Eigen::Isometry3d> truth = OneMillimetreNearerTheWall();
  const std::vector<WindowKeyFrame> window =
      ExactWindowHoldingTheFirst(camera, truth, PointsSeenFromEach(camera, truth, 110));
  WindowAdjustmentOptions options;
  options.max_iterations = 50;
  options.cross_section_anchor_xy = Eigen::Vector2d::Zero();
  options.cross_section_anchor_sigma_m = 1.0;
  std::vector<WindowKeyFrame> loose = window;
  AdjustWindow(camera, kRadius, options, &loose);
  for (int a = 1; a < 6; ++a) {
    EXPECT_LT((loose[a].pose.translation() - truth[a].translation()).norm(), 1e-6) << a;
  }
  options.cross_section_anchor_sigma_m = 1e-8;
  std::vector<WindowKeyFrame> stiff = window;
  AdjustWindow(camera, kRadius, options, &stiff);
  EXPECT_EQ(stiff[0].pose.translation(), truth[0].translation());
  for (int a = 1; a < 6; ++a) {
    EXPECT_LT(stiff[a].pose.translation().head<2>().norm(), 1e-5) << a;
  }
}

// The robust anchor: the same key frames, 1 mm off the anchor, with an anchor of sigma 0.01 mm.
// The Gaussian anchor pulls them most of the way onto it; the Cauchy one lets the reprojections,
// which see the 1 mm through the 6-inch pipe's curvature, overrule it.
TEST(AdjustWindow, RobustCrossSectionAnchorIsOverruledByTheImages) {
  const Camera camera = SteelSixInchCamera();
  const std::vector<Eigen::Isometry3d> truth = OneMillimetreNearerTheWall();
  const std::vector<WindowKeyFrame> window =
      ExactWindowHoldingTheFirst(camera, truth, PointsSeenFromEach(camera, truth, 110));
  WindowAdjustmentOptions options;
  options.max_iterations = 50;
  options.cross_section_anchor_xy = Eigen::Vector2d::Zero();
  options.cross_section_anchor_sigma_m = 0.00001;
  std::vector<WindowKeyFrame> gaussian = window;
  AdjustWindow(camera, kRadius, options, &gaussian);
  options.cross_section_anchor_robust = true;
  std::vector<WindowKeyFrame> robust = window;
  AdjustWindow(camera, kRadius, options, &robust);
  for (int a = 1; a < 6; ++a) {
    const double gaussian_error = (gaussian[a].pose.translation() - truth[a].translation()).norm();
    const double robust_error = (robust[a].pose.translation() - truth[a].translation()).norm();
    std::printf("key frame %d: off the truth by %.4f mm (Gaussian) and %.4f mm (robust)\n", a,
                1000 * gaussian_error, 1000 * robust_error);
    EXPECT_GT(gaussian_error, 0.0005) << a;
    EXPECT_LT(robust_error, 0.0001) << a;
  }
}

}  // namespace
}  // namespace pipescope
