#include "pipescope/geometry/pipe_cylinder.h"

#include <gtest/gtest.h>

#include <cmath>

namespace pipescope {
namespace {

TEST(RayToWall, MatchesTheClosedFormAndSkipsAxialRays) {
  // From the axis every ray across the pipe travels r / |sin(angle to the axis)|.
  const Eigen::Vector3d tilted = Eigen::Vector3d(0.6, 0.0, 0.8);
  EXPECT_NEAR(*RayToWall(Eigen::Vector3d(0, 0, 5), tilted, 0.2), 0.2 / 0.6, 1e-15);
  // From 0.05 m below the axis towards the floor (+Y) and towards the ceiling (-Y).
  const Eigen::Vector3d origin(0.0, -0.05, 0.0);
  EXPECT_NEAR(*RayToWall(origin, Eigen::Vector3d::UnitY(), 0.2), 0.25, 1e-15);
  EXPECT_NEAR(*RayToWall(origin, -Eigen::Vector3d::UnitY(), 0.2), 0.15, 1e-15);
  // Sideways from there: sqrt(r^2 - 0.05^2), and the hit lies on the wall.
  const double t = *RayToWall(origin, Eigen::Vector3d::UnitX(), 0.2);
  EXPECT_NEAR(t, std::sqrt(0.2 * 0.2 - 0.05 * 0.05), 1e-15);
  EXPECT_FALSE(RayToWall(origin, Eigen::Vector3d::UnitZ(), 0.2).has_value());
}

}  // namespace
}  // namespace pipescope
