#include "pipescope/geometry/clock_position.h"

#include <gtest/gtest.h>

#include <cmath>

namespace pipescope {
namespace {

const Eigen::Vector3d kAlongZ = Eigen::Vector3d::UnitZ();
const Eigen::Vector3d kUpIsMinusY(0.0, -1.0, 0.0);

TEST(ClockPosition, QuarterHoursLookingAlongTravel) {
  // Looking along +Z with -Y up, +X is on the right (OpenCV's camera frame): 3 o'clock.
  EXPECT_NEAR(*ClockAngleDeg({0, -1, 0}, kAlongZ, kUpIsMinusY), 0.0, 1e-12);
  EXPECT_NEAR(*ClockAngleDeg({1, 0, 0}, kAlongZ, kUpIsMinusY), 90.0, 1e-12);
  EXPECT_NEAR(*ClockAngleDeg({0, 1, 0}, kAlongZ, kUpIsMinusY), 180.0, 1e-12);
  EXPECT_NEAR(*ClockAngleDeg({-1, 0, 0}, kAlongZ, kUpIsMinusY), 270.0, 1e-12);
  // Travelling the other way mirrors the face: +X is now on the left.
  EXPECT_NEAR(*ClockAngleDeg({1, 0, 0}, -kAlongZ, kUpIsMinusY), 270.0, 1e-12);
}

TEST(ClockPosition, IgnoresTheAxialPartsAndTheLengths) {
  const Eigen::Vector3d up(0.0, -3.0, 5.0);  // tilted towards the axis
  const double angle = 30.0 * M_PI / 180.0;  // 1 o'clock
  const Eigen::Vector3d radial(2.0 * std::sin(angle), -2.0 * std::cos(angle), -7.0);
  EXPECT_NEAR(*ClockAngleDeg(radial, kAlongZ, up), 30.0, 1e-9);
}

TEST(ClockPosition, UndefinedWhenUpRunsAlongThePipe) {
  EXPECT_FALSE(ClockAngleDeg({1, 0, 0}, kAlongZ, {0, 0, 1}).has_value());
  EXPECT_FALSE(ClockAngleDeg({0, 0, 1}, kAlongZ, kUpIsMinusY).has_value());
}

TEST(ClockPosition, ClockStrings) {
  EXPECT_EQ(ClockString(0.0), "12:00");
  EXPECT_EQ(ClockString(90.0), "3:00");
  EXPECT_EQ(ClockString(345.0), "11:30");
  EXPECT_EQ(ClockString(359.9), "12:00");
  EXPECT_EQ(ClockString(-90.0), "9:00");
  EXPECT_EQ(ClockString(15.5), "12:31");
}

TEST(ClockPosition, CameraUprightIsMinusY) {
  const Eigen::Matrix3d identity = Eigen::Matrix3d::Identity();
  EXPECT_EQ(CameraUpright(identity), Eigen::Vector3d(0.0, -1.0, 0.0));
  // A camera rolled 90 degrees about its optical axis (z): its -y points along world +x.
  Eigen::Matrix3d rolled;
  rolled << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  EXPECT_TRUE(CameraUpright(rolled).isApprox(Eigen::Vector3d(1.0, 0.0, 0.0)));
}

}  // namespace
}  // namespace pipescope
