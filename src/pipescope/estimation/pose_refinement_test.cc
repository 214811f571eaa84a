#include "pipescope/estimation/pose_refinement.h"

#include <gtest/gtest.h>

#include "pipescope/estimation/estimation_testing.h"

namespace pipescope {
namespace {

constexpr double kRadius = 0.07666;
constexpr double kReference = M_PI / 2.0;

// The tracks' means are the true wall points; a pose 1 mm and 0.5 degrees off is pulled back to
// the truth (000 §5.3.3 with exact statistics).
Eigen::Isometry3d TruePose() {
  Eigen::Isometry3d truth = WallLookingPose({0.002, -0.003, 0.4});
  truth.linear() = Eigen::AngleAxisd(0.01, Eigen::Vector3d(1, 2, 3).normalized()) * truth.linear();
  return truth;
}

// Observations whose tracks' means are the true wall points seen from `truth`.
std::vector<SurfaceObservation> ExactObservations(const Eigen::Isometry3d& truth) {
  std::vector<SurfaceObservation> observations;
  for (const Eigen::Vector3d& point :
       WallPointsSeenFrom(SteelSixInchCamera(), truth, kRadius, 150, 3)) {
    SurfaceObservation o;
    o.bearing = (truth.inverse() * point).normalized();
    o.track.Add(ToSurface(point, kRadius, kReference));
    o.track.Add(ToSurface(point, kRadius, kReference));
    observations.push_back(o);
  }
  return observations;
}

TEST(RefinePoseOnSurface, RecoversThePoseFromExactStatistics) {
  const Eigen::Isometry3d truth = TruePose();
  const std::vector<SurfaceObservation> observations = ExactObservations(truth);
  Eigen::Isometry3d start = truth;
  start.translation() += Eigen::Vector3d(0.0007, -0.0005, 0.001);
  start.linear() =
      Eigen::AngleAxisd(0.5 * M_PI / 180.0, Eigen::Vector3d(0, 1, 1).normalized()) * start.linear();
  const Eigen::Isometry3d refined =
      RefinePoseOnSurface(start, observations, kRadius, kReference, PoseRefinementOptions{});
  EXPECT_LT((refined.translation() - truth.translation()).norm(), 1e-6);
  EXPECT_LT(Eigen::AngleAxisd(refined.linear() * truth.linear().transpose()).angle(), 1e-5);
}

// A correction larger than the limit (a fraction of the radius) is not taken: the start pose,
// 3 mm off, stays; with the limit raised (or off) the same start is pulled to the truth.
TEST(RefinePoseOnSurface, KeepsThePoseWhenTheCorrectionIsTooLarge) {
  const Eigen::Isometry3d truth = TruePose();
  const std::vector<SurfaceObservation> observations = ExactObservations(truth);
  Eigen::Isometry3d start = truth;
  start.translation() += Eigen::Vector3d(0.003, 0.0, 0.0);
  PoseRefinementOptions options;
  ASSERT_LT(options.max_position_change_radii * kRadius, 0.003);
  EXPECT_TRUE(
      RefinePoseOnSurface(start, observations, kRadius, kReference, options).isApprox(start));
  options.max_position_change_radii = 0.0;
  const Eigen::Isometry3d refined =
      RefinePoseOnSurface(start, observations, kRadius, kReference, options);
  EXPECT_LT((refined.translation() - truth.translation()).norm(), 1e-6);
}

TEST(RefinePoseOnSurface, KeepsThePoseWithTooFewObservations) {
  const Eigen::Isometry3d start = WallLookingPose({0.0, 0.0, 0.0});
  const Eigen::Isometry3d refined = RefinePoseOnSurface(start, {}, kRadius, kReference, {});
  EXPECT_TRUE(refined.isApprox(start));
}

}  // namespace
}  // namespace pipescope
