#include "pipescope/estimation/initial_position.h"

#include <gtest/gtest.h>

#include "pipescope/estimation/estimation_testing.h"
#include "pipescope/estimation/surface_point.h"

namespace pipescope {
namespace {

constexpr double kRadius = 0.07666;

// Ten key frames 8 mm apart of a camera offset from the axis; every wall point is seen by the
// frames whose image it falls in. Started on the axis with the steps guessed 10 % short, the
// optimisation must find the offset and the steps (000 §5.3.2).
TEST(OptimiseInitialPosition, RecoversAKnownOffsetAndSteps) {
  const Camera camera = SteelSixInchCamera();
  const Eigen::Vector2d true_c_xy(0.003, -0.006);
  std::vector<double> true_h, guess_h;
  std::vector<Eigen::Isometry3d> poses;
  for (int a = 0; a < 10; ++a) {
    true_h.push_back(0.008 * a);
    guess_h.push_back(0.9 * 0.008 * a);
    poses.push_back(WallLookingPose({true_c_xy.x(), true_c_xy.y(), true_h.back()}));
  }
  std::vector<Eigen::Vector3d> points;
  for (int a = 0; a < 10; ++a) {
    for (const Eigen::Vector3d& p : WallPointsSeenFrom(camera, poses[a], kRadius, 40, 100 + a)) {
      points.push_back(p);
    }
  }
  std::vector<std::vector<KeyFrameKeypoint>> key_frames(10);
  for (std::size_t g = 0; g < points.size(); ++g) {
    for (int a = 0; a < 10; ++a) {
      const Eigen::Vector3d in_camera = poses[a].inverse() * points[g];
      Eigen::Vector2d pixel;
      if (camera.Project(in_camera, &pixel) != ProjectionStatus::kValid) continue;
      Eigen::Vector3d bearing;
      ASSERT_TRUE(camera.Unproject(pixel, &bearing));
      key_frames[a].push_back({static_cast<long long>(g), pixel, bearing});
    }
  }
  InitialPositionOptions options;
  options.max_iterations = 100;
  const InitialPositionResult result =
      OptimiseInitialPosition(camera, WallLookingRotation(), kRadius, Eigen::Vector2d::Zero(),
                              guess_h, key_frames, options);
  EXPECT_GT(result.initial_rms_px, 1.0);
  EXPECT_LT(result.final_rms_px, 1e-4);
  EXPECT_NEAR(result.c_xy.x(), true_c_xy.x(), 1e-6);
  EXPECT_NEAR(result.c_xy.y(), true_c_xy.y(), 1e-6);
  for (int a = 0; a < 10; ++a) EXPECT_NEAR(result.delta_h[a], true_h[a], 1e-6) << a;
}

}  // namespace
}  // namespace pipescope
