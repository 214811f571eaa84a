#include "pipescope/estimation/cylinder_scale.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "pipescope/estimation/straight_cylinder_error.h"

namespace pipescope {
namespace {

constexpr double kRadius = 0.2;

// Wall points of a pipe whose axis is `axis` (in the camera frame), seen from the origin.
std::vector<Eigen::Vector3d> WallPoints(const PipeAxis& axis, int count, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const Eigen::Vector3d a = axis.direction.normalized();
  const Eigen::Vector3d u = a.unitOrthogonal();
  const Eigen::Vector3d v = a.cross(u);
  std::vector<Eigen::Vector3d> points;
  for (int k = 0; k < count; ++k) {
    const double phi = 2.0 * M_PI * uniform(rng);
    const double along = 0.05 + 0.5 * uniform(rng);
    points.push_back(axis.point + along * a + kRadius * (std::cos(phi) * u + std::sin(phi) * v));
  }
  return points;
}

TEST(CylinderScale, RecoversTheScaleExactlyWithTheAxisThroughTheCamera) {
  const PipeAxis axis;  // the optical axis
  std::vector<Eigen::Vector3d> points = WallPoints(axis, 50, 1);
  const double true_scale = 0.0123;  // e.g. a 12.3 mm baseline
  for (Eigen::Vector3d& point : points) point /= true_scale;
  EXPECT_NEAR(ScaleFromCylinderRadius(points, axis, kRadius), true_scale, 1e-12);
}

TEST(CylinderScale, RecoversTheScaleWithAnOffsetTiltedAxis) {
  PipeAxis axis;
  axis.point = Eigen::Vector3d(0.03, -0.02, 0.0);
  axis.direction = Eigen::Vector3d(0.05, -0.03, 1.0).normalized();
  std::vector<Eigen::Vector3d> points = WallPoints(axis, 80, 2);
  const double true_scale = 0.0087;
  for (Eigen::Vector3d& point : points) point /= true_scale;
  // Every point is on the wall at the true scale: e_i(s) = 0 for all i.
  EXPECT_NEAR(ScaleFromCylinderRadius(points, axis, kRadius), true_scale, 1e-9 * true_scale);
}

TEST(CylinderScale, IsRobustToNoiseAndOutliers) {
  PipeAxis axis;
  axis.point = Eigen::Vector3d(0.01, 0.0, 0.0);
  std::vector<Eigen::Vector3d> points = WallPoints(axis, 200, 3);
  std::mt19937_64 rng(4);
  std::normal_distribution<double> depth_noise(0.0, 0.01);
  const double true_scale = 0.01;
  for (std::size_t k = 0; k < points.size(); ++k) {
    // 1 % depth noise along the ray (unbiased), and every fifth point far off the wall.
    double factor = 1.0 + depth_noise(rng);
    if (k % 5 == 0) factor = 3.0;
    points[k] *= factor / true_scale;
  }
  EXPECT_NEAR(ScaleFromCylinderRadius(points, axis, kRadius), true_scale, 0.003 * true_scale);
}

TEST(CylinderScale, FitsScaleAndAxisFromAPoorStart) {
  // Points of a tilted, offset pipe; the fit starts from the optical axis (5 degrees and 30 mm
  // off) and must find the true axis and scale to the noise level.
  PipeAxis truth;
  truth.point = Eigen::Vector3d(0.03, -0.02, 0.0);
  truth.direction = Eigen::Vector3d(0.06, 0.05, 1.0).normalized();
  std::vector<Eigen::Vector3d> points = WallPoints(truth, 150, 6);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> depth_noise(0.0, 0.005);
  const double true_scale = 0.011;
  for (std::size_t k = 0; k < points.size(); ++k) {
    const double factor = k % 10 == 0 ? 2.0 : 1.0 + depth_noise(rng);  // 10 % far off the wall
    points[k] *= factor / true_scale;
  }
  PipeAxis axis;  // the optical axis
  const double scale = FitScaleAndAxis(points, kRadius, &axis);
  EXPECT_NEAR(scale, true_scale, 0.003 * true_scale);
  EXPECT_GT(axis.direction.dot(truth.direction), std::cos(0.5 * M_PI / 180.0));
  const Eigen::Vector3d offset = axis.point - truth.point;
  EXPECT_LT((offset - offset.dot(truth.direction) * truth.direction).norm(), 0.001);
}

TEST(CylinderScale, NoPointOffTheAxisGivesZero) {
  const PipeAxis axis;
  EXPECT_EQ(ScaleFromCylinderRadius({Eigen::Vector3d(0, 0, 1)}, axis, kRadius), 0.0);
  EXPECT_EQ(ScaleFromCylinderRadius({}, axis, kRadius), 0.0);
}

TEST(CylinderScale, AxisOfTheWindowCylinderHasZeroWallErrorAtTheRadius) {
  // Points on the axis returned for a cylinder parameter vector lie at distance r from it in
  // StraightCylinderError (eq. 6) too, with the first pose at the identity.
  const double cylinder[4] = {0.05, -0.03, 0.012, -0.007};
  const PipeAxis axis = StraightCylinderAxis(cylinder);
  const double identity_rotation[4] = {1, 0, 0, 0};
  const double zero_translation[3] = {0, 0, 0};
  const StraightCylinderError error(kRadius, 1.0);
  for (const Eigen::Vector3d& point : WallPoints(axis, 20, 5)) {
    double residual;
    error(cylinder, identity_rotation, zero_translation, point.data(), &residual);
    EXPECT_NEAR(residual, 0.0, 1e-12);
  }
}

}  // namespace
}  // namespace pipescope
