#include "pipescope/geometry/t_intersection.h"

#include <gtest/gtest.h>

#include <cmath>

namespace pipescope {
namespace {

constexpr double kDeg = M_PI / 180.0;

// A camera pose from a turn about an axis and a place.
Eigen::Isometry3d Pose(double angle, const Eigen::Vector3d& axis, const Eigen::Vector3d& place) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
  pose.translation() = place;
  return pose;
}

// Distance of a point from a line given by a point and a direction.
double DistanceFromLine(const Eigen::Vector3d& x, const PipeAxis& line) {
  const Eigen::Vector3d d = line.direction.normalized();
  const Eigen::Vector3d v = x - line.point;
  return (v - v.dot(d) * d).norm();
}

PipeAxis AxisInWorld(const Eigen::Isometry3d& world_from_camera, const double cylinder[4]) {
  const PipeAxis in_camera = StraightCylinderAxis(cylinder);
  return {world_from_camera * in_camera.point, world_from_camera.linear() * in_camera.direction};
}

struct Case {
  double red_cylinder[4];
  double blue_cylinder[4];
  double model[kTIntersectionParameters];
};

// A T met at 70 degrees (not 90), each camera off its axis and tilted.
Case ObliqueT() {
  return {{0.03, -0.02, 0.015, -0.01},
          {-0.04, 0.025, -0.02, 0.012},
          {0.4, 1.3, -0.7, 1.1, 70.0 * kDeg}};
}

TEST(TIntersection, TheAxesMeetAtTheCentreAtTheModelsAngle) {
  const Case c = ObliqueT();
  const Eigen::Isometry3d world_from_red = Pose(0.3, {0.2, 1.0, 0.1}, {1.0, -0.5, 2.0});
  const TIntersectionGeometry t =
      TIntersectionInWorld(world_from_red, c.red_cylinder, c.blue_cylinder, c.model);
  // Checked through eq. 4's axis of each cylinder (StraightCylinderAxis), not through D.
  const PipeAxis red = AxisInWorld(world_from_red, c.red_cylinder);
  const PipeAxis blue = AxisInWorld(t.world_from_blue_camera, c.blue_cylinder);
  EXPECT_LT(DistanceFromLine(t.centre, red), 1e-12);
  EXPECT_LT(DistanceFromLine(t.centre, blue), 1e-12);
  EXPECT_NEAR(std::acos(red.direction.normalized().dot(blue.direction.normalized())), 70.0 * kDeg,
              1e-12);
  // l_r and l_b are the distances from I of each camera's foot on its axis.
  const auto foot = [](const Eigen::Vector3d& x, const PipeAxis& line) {
    const Eigen::Vector3d d = line.direction.normalized();
    return Eigen::Vector3d(line.point + (x - line.point).dot(d) * d);
  };
  EXPECT_NEAR((foot(world_from_red.translation(), red) - t.centre).norm(), 1.3, 1e-12);
  EXPECT_NEAR((foot(t.world_from_blue_camera.translation(), blue) - t.centre).norm(), 1.1, 1e-12);
  // The directions point from I towards each camera's foot.
  EXPECT_GT(t.red_direction.dot(world_from_red.translation() - t.centre), 1.2);
  EXPECT_GT(t.blue_direction.dot(t.world_from_blue_camera.translation() - t.centre), 1.0);
}

TEST(TIntersection, FitRecoversTheModelFromTheTwoPoses) {
  for (const double phi_deg : {90.0, 45.0, 135.0}) {
    Case c = ObliqueT();
    c.model[kPhi] = phi_deg * kDeg;
    const Eigen::Isometry3d world_from_red = Pose(-0.8, {1.0, 0.3, -0.4}, {-2.0, 0.1, 0.7});
    const Eigen::Isometry3d world_from_blue =
        world_from_red * RedCameraFromBlueCamera(c.red_cylinder, c.blue_cylinder, c.model);
    double gap = 1.0;
    const auto fitted = FitTIntersectionModel(world_from_red, c.red_cylinder, world_from_blue,
                                              c.blue_cylinder, 5.0 * kDeg, &gap);
    ASSERT_TRUE(fitted.has_value()) << phi_deg;
    for (int k = 0; k < kTIntersectionParameters; ++k) {
      EXPECT_NEAR((*fitted)(k), c.model[k], 1e-9) << phi_deg << " parameter " << k;
    }
    EXPECT_LT(gap, 1e-9);
  }
}

TEST(TIntersection, FitMeasuresTheGapOfAxesThatMiss) {
  const Case c = ObliqueT();
  const Eigen::Isometry3d world_from_red = Pose(0.0, {0, 0, 1}, {0, 0, 0});
  Eigen::Isometry3d world_from_blue =
      world_from_red * RedCameraFromBlueCamera(c.red_cylinder, c.blue_cylinder, c.model);
  // Shift the blue camera along the common normal of the two axes by 4 mm.
  const PipeAxis red = AxisInWorld(world_from_red, c.red_cylinder);
  const PipeAxis blue = AxisInWorld(world_from_blue, c.blue_cylinder);
  const Eigen::Vector3d normal = red.direction.cross(blue.direction).normalized();
  world_from_blue.translation() += 0.004 * normal;
  double gap = 0.0;
  const auto fitted = FitTIntersectionModel(world_from_red, c.red_cylinder, world_from_blue,
                                            c.blue_cylinder, 5.0 * kDeg, &gap);
  ASSERT_TRUE(fitted.has_value());
  EXPECT_NEAR(gap, 0.004, 1e-9);
  EXPECT_NEAR((*fitted)(kPhi), c.model[kPhi], 1e-9);
}

TEST(TIntersection, ParallelAxesHaveNoModel) {
  const double cylinder[4] = {0, 0, 0, 0};
  const Eigen::Isometry3d world_from_red = Eigen::Isometry3d::Identity();
  const Eigen::Isometry3d world_from_blue = Pose(2.0 * kDeg, {1, 0, 0}, {0, 0, 3.0});
  EXPECT_FALSE(
      FitTIntersectionModel(world_from_red, cylinder, world_from_blue, cylinder, 5.0 * kDeg)
          .has_value());
  const Eigen::Isometry3d reversed = Pose(178.0 * kDeg, {1, 0, 0}, {0, 0, 3.0});
  EXPECT_FALSE(
      FitTIntersectionModel(world_from_red, cylinder, reversed, cylinder, 5.0 * kDeg).has_value());
}

TEST(TIntersection, PointsGoToTheNearerCylinder) {
  // A right-angled T, I at z = 1 on the red axis, the blue axis along red X through I.
  const double model[kTIntersectionParameters] = {0.0, 1.0, 0.0, 0.8, 90.0 * kDeg};
  const double r = 0.2;
  double distance = 1.0;
  // On the red wall well before the junction.
  EXPECT_FALSE(NearerIsBlueCylinder({0.0, r + 0.003, 0.2}, model, r, &distance));
  EXPECT_NEAR(distance, 0.003, 1e-12);
  // On the blue wall well down the branch: there the red axis is about 0.6 m away.
  EXPECT_TRUE(NearerIsBlueCylinder({0.6, -0.002 - r, 1.0}, model, r, &distance));
  EXPECT_NEAR(distance, 0.002, 1e-12);
  // On the blue wall, just inside the red cylinder's radius: nearer to the blue wall still.
  EXPECT_TRUE(NearerIsBlueCylinder({0.15, 0.0, 1.0 + r - 0.001}, model, r, &distance));
  EXPECT_NEAR(distance, -0.001, 1e-12);
}

}  // namespace
}  // namespace pipescope
