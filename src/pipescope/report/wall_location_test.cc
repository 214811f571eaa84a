#include "pipescope/report/wall_location.h"

#include <gtest/gtest.h>

#include <cmath>

namespace pipescope {
namespace {

constexpr double kRadius = 0.2;

Camera Pinhole() {
  return Camera(CameraModelId::kPinholeRadtan, 640, 480,
                {400.0, 400.0, 319.5, 239.5, 0.01, -0.005, 0.0, 0.0, 0.0});
}

// The wall point at clock angle `clock_deg` (up = -Y, looking along +Z: 3 o'clock is +X) and z.
Eigen::Vector3d WallPoint(double clock_deg, double z) {
  const double a = clock_deg * M_PI / 180.0;
  return {kRadius * std::sin(a), -kRadius * std::cos(a), z};
}

TEST(WallLocation, FindsTheWallPointAPixelShows) {
  // A camera off the axis, looking forward and towards the 4 o'clock wall.
  Eigen::Isometry3d world_from_cam = Eigen::Isometry3d::Identity();
  world_from_cam.translation() = Eigen::Vector3d(0.03, -0.02, 1.0);
  world_from_cam.linear() = Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitY()).toRotationMatrix() *
                            Eigen::AngleAxisd(-0.3, Eigen::Vector3d::UnitX()).toRotationMatrix();
  Station station;
  station.distance_m = 0.75;  // the camera's own distance along the pipe
  station.travel = Eigen::Vector3d::UnitZ();
  const Camera camera = Pinhole();
  for (const double clock : {100.0, 120.0, 140.0}) {
    for (const double z : {1.15, 1.3}) {
      const Eigen::Vector3d truth = WallPoint(clock, z);
      Eigen::Vector2d pixel;
      ASSERT_EQ(camera.Project(world_from_cam.inverse() * truth, &pixel), ProjectionStatus::kValid);
      const std::optional<WallLocation> found =
          LocateOnCylinder(camera, world_from_cam, station, pixel, kRadius, {}, {0, -1, 0});
      ASSERT_TRUE(found.has_value());
      EXPECT_LT((found->point - truth).norm(), 1e-9);
      EXPECT_NEAR(found->distance_m, 0.75 + (z - 1.0), 1e-9);
      EXPECT_NEAR(found->clock_angle_deg, clock, 1e-7);
    }
  }
  // Travelling along -Z, the same point lies behind (smaller distance) and the face mirrors.
  station.travel = -Eigen::Vector3d::UnitZ();
  Eigen::Vector2d pixel;
  camera.Project(world_from_cam.inverse() * WallPoint(120.0, 1.3), &pixel);
  const auto mirrored =
      LocateOnCylinder(camera, world_from_cam, station, pixel, kRadius, {}, {0, -1, 0});
  ASSERT_TRUE(mirrored.has_value());
  EXPECT_NEAR(mirrored->distance_m, 0.75 - 0.3, 1e-9);
  EXPECT_NEAR(mirrored->clock_angle_deg, 240.0, 1e-7);
  EXPECT_EQ(mirrored->clock, "8:00");
}

// The same scene moved and turned as a whole: the axis no longer the Z axis through the origin.
TEST(WallLocation, AnyAxisGivesTheSameAnswerAsTheMovedScene) {
  const Eigen::Isometry3d move =
      Eigen::Translation3d(0.4, -1.0, 2.0) *
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1.0, 2.0, -0.5).normalized());
  Eigen::Isometry3d world_from_cam = Eigen::Isometry3d::Identity();
  world_from_cam.translation() = Eigen::Vector3d(-0.02, 0.05, 0.3);
  world_from_cam.linear() = Eigen::AngleAxisd(-0.4, Eigen::Vector3d::UnitY()).toRotationMatrix();
  Station station;
  station.travel = Eigen::Vector3d::UnitZ();
  const Camera camera = Pinhole();
  const Eigen::Vector3d truth = WallPoint(250.0, 0.45);
  Eigen::Vector2d pixel;
  ASSERT_EQ(camera.Project(world_from_cam.inverse() * truth, &pixel), ProjectionStatus::kValid);
  Station moved_station = station;
  moved_station.travel = move.linear() * station.travel;
  const PipeAxis moved_axis{move.translation(), move.linear() * Eigen::Vector3d::UnitZ()};
  const auto found = LocateOnCylinder(camera, move * world_from_cam, moved_station, pixel, kRadius,
                                      moved_axis, move.linear() * Eigen::Vector3d(0, -1, 0));
  ASSERT_TRUE(found.has_value());
  EXPECT_LT((found->point - move * truth).norm(), 1e-9);
  EXPECT_NEAR(found->distance_m, 0.15, 1e-9);
  EXPECT_NEAR(found->clock_angle_deg, 250.0, 1e-7);
  // A camera outside the cylinder has no answer.
  EXPECT_FALSE(LocateOnCylinder(camera, world_from_cam, station, pixel, 0.01, {}, {0, -1, 0}));
}

TEST(WallLocation, ClockSpanTakesTheShortArc) {
  auto [from, to] = ClockSpan({350.0, 10.0, 0.0});
  EXPECT_DOUBLE_EQ(from, 350.0);
  EXPECT_DOUBLE_EQ(to, 10.0);
  std::tie(from, to) = ClockSpan({50.0, 10.0, 30.0, std::nan("")});
  EXPECT_DOUBLE_EQ(from, 10.0);
  EXPECT_DOUBLE_EQ(to, 50.0);
  std::tie(from, to) = ClockSpan({-30.0, 400.0});
  EXPECT_DOUBLE_EQ(from, 330.0);
  EXPECT_DOUBLE_EQ(to, 40.0);
  EXPECT_TRUE(std::isnan(ClockSpan({}).first));
}

}  // namespace
}  // namespace pipescope
