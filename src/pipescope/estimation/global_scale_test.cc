#include "pipescope/estimation/global_scale.h"

#include <gtest/gtest.h>

#include "pipescope/estimation/estimation_testing.h"

namespace pipescope {
namespace {

constexpr double kRadius = 0.07666;

// Key frames whose positions all carry the same cross-section error and travel scale (what a
// biased first window leaves): the correction must find (dX, dY, s) and restore the truth.
TEST(CorrectGlobalScale, RemovesACommonOffsetAndScale) {
  const Camera camera = SteelSixInchCamera();
  std::vector<Eigen::Isometry3d> truth;
  for (int a = 0; a < 12; ++a) {
    Eigen::Isometry3d pose =
        WallLookingPose({0.001 * std::sin(a), 0.0005 * std::cos(a), 0.012 * a});
    pose.linear() =
        Eigen::AngleAxisd(0.004 * std::sin(a), Eigen::Vector3d::UnitX()) * pose.linear();
    truth.push_back(pose);
  }
  std::vector<Eigen::Vector3d> points;
  for (int a = 0; a < 12; ++a) {
    for (const Eigen::Vector3d& p : WallPointsSeenFrom(camera, truth[a], kRadius, 40, 70 + a)) {
      points.push_back(p);
    }
  }
  std::vector<WindowKeyFrame> key_frames(12);
  const Eigen::Vector2d error_xy(-0.0008, 0.0015);
  const double error_scale = 0.985;
  for (int a = 0; a < 12; ++a) {
    key_frames[a].pose = truth[a];
    const Eigen::Vector3d c = truth[a].translation();
    key_frames[a].pose.translation() = Eigen::Vector3d(c.x() + error_xy.x(), c.y() + error_xy.y(),
                                                       error_scale * (c.z() - 0.0) + 0.0);
    key_frames[a].keypoints = ObservedKeypoints(camera, truth[a], points);
  }
  GlobalScaleOptions options;
  options.max_iterations = 50;
  const GlobalScaleResult result = CorrectGlobalScale(camera, kRadius, options, &key_frames);
  EXPECT_GT(result.initial_rms_px, 0.5);
  EXPECT_LT(result.final_rms_px, 1e-4);
  EXPECT_NEAR(result.offset_xy.x(), -error_xy.x(), 1e-6);
  EXPECT_NEAR(result.offset_xy.y(), -error_xy.y(), 1e-6);
  EXPECT_NEAR(result.scale, 1.0 / error_scale, 1e-5);
  for (int a = 0; a < 12; ++a) {
    EXPECT_LT((key_frames[a].pose.translation() - truth[a].translation()).norm(), 1e-6) << a;
  }
}

}  // namespace
}  // namespace pipescope
