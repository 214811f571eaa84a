#include "pipescope/estimation/axial_step.h"

#include <gtest/gtest.h>

#include "pipescope/estimation/estimation_testing.h"

namespace pipescope {
namespace {

constexpr double kRadius = 0.07666;
constexpr double kReference = M_PI / 2.0;

// Key frame a sees wall points; the new key frame, delta_h further, sees the same points. The
// statistics hold the points' estimates from a; the new frame's rays are cast from a's pose
// (delta_h = 0) and the solver must find the true delta_h.
std::vector<AxialStepObservation> Synthetic(double true_delta_h, int outliers, int estimates) {
  const Camera camera = SteelSixInchCamera();
  const Eigen::Isometry3d a = WallLookingPose({0.001, -0.002, 0.5});
  Eigen::Isometry3d b = a;
  b.translation().z() += true_delta_h;
  std::vector<AxialStepObservation> observations;
  int index = 0;
  for (const Eigen::Vector3d& point : WallPointsSeenFrom(camera, b, kRadius, 200, 11)) {
    AxialStepObservation o;
    for (int j = 0; j < estimates; ++j) o.track.Add(ToSurface(point, kRadius, kReference));
    Eigen::Vector3d bearing = (b.inverse() * point).normalized();
    if (index++ < outliers) bearing = (bearing + Eigen::Vector3d(0.05, 0.0, 0.0)).normalized();
    o.predicted = ToSurface(*WallPointOfBearing(a, bearing, kRadius), kRadius, kReference);
    observations.push_back(o);
  }
  return observations;
}

TEST(EstimateAxialStep, RecoversAKnownStepExactly) {
  AxialStepOptions plain;
  plain.huber_m = 0.0;
  EXPECT_NEAR(EstimateAxialStep(Synthetic(0.0123, 0, 3), plain), 0.0123, 1e-12);
  EXPECT_NEAR(EstimateAxialStep(Synthetic(-0.0071, 0, 1), plain), -0.0071, 1e-12);
}

TEST(EstimateAxialStep, HuberWeightsResistOutliers) {
  const std::vector<AxialStepObservation> observations = Synthetic(0.0123, 20, 2);
  AxialStepOptions plain;
  plain.huber_m = 0.0;
  const double least_squares = EstimateAxialStep(observations, plain);
  int inliers = 0;
  const double robust = EstimateAxialStep(observations, AxialStepOptions{}, &inliers);
  EXPECT_GT(std::abs(least_squares - 0.0123), 1e-4);  // 10 % outliers pull plain LS off
  EXPECT_LT(std::abs(robust - 0.0123), 0.2 * std::abs(least_squares - 0.0123));
  EXPECT_EQ(inliers, 180);
}

TEST(EstimateAxialStep, NoObservationsMeansNoStep) { EXPECT_EQ(EstimateAxialStep({}, {}), 0.0); }

}  // namespace
}  // namespace pipescope
