#include "pipescope/estimation/surface_point.h"

#include <gtest/gtest.h>

#include <cmath>

#include "pipescope/estimation/estimation_testing.h"
#include "pipescope/estimation/track_statistics.h"

namespace pipescope {
namespace {

constexpr double kRadius = 0.07666;

TEST(WallPointOfBearing, OpticalAxisFromTheAxisMeetsTheWallAtTheRadius) {
  const Eigen::Isometry3d pose = WallLookingPose({0.0, 0.0, 0.3});
  const auto wall = WallPointOfBearing(pose, Eigen::Vector3d::UnitZ(), kRadius);
  ASSERT_TRUE(wall);
  EXPECT_NEAR((*wall - Eigen::Vector3d(0.0, kRadius, 0.3)).norm(), 0.0, 1e-12);
}

TEST(WallPointOfBearing, OffAxisCameraMatchesTheClosedForm) {
  // From (cx, cy) looking along +Y the ray meets x = cx at y = sqrt(r^2 - cx^2) (eq. 37 with
  // R_1 eta = 0, R_2 eta = 1: kappa = sqrt(r^2 - cx^2) - cy).
  const double cx = 0.004, cy = -0.01;
  const Eigen::Isometry3d pose = WallLookingPose({cx, cy, 0.0});
  const auto wall = WallPointOfBearing(pose, Eigen::Vector3d::UnitZ(), kRadius);
  ASSERT_TRUE(wall);
  EXPECT_NEAR(wall->x(), cx, 1e-12);
  EXPECT_NEAR(wall->y(), std::sqrt(kRadius * kRadius - cx * cx), 1e-12);
  // A slanted bearing: (0.3, 0.4, 1) in the camera is (0.4, 1, 0.3) in the pipe (cam y -> X,
  // cam z -> Y, cam x -> Z); kappa solves (cx + 0.4 k)^2 + (cy + k)^2 = r^2 for k > 0.
  const Eigen::Vector3d bearing(0.3, 0.4, 1.0);
  const double a = 0.16 + 1.0, b = 2.0 * (0.4 * cx + cy), c = cx * cx + cy * cy - kRadius * kRadius;
  const double k = (-b + std::sqrt(b * b - 4 * a * c)) / (2 * a);
  const auto slanted = WallPointOfBearing(pose, bearing, kRadius);
  ASSERT_TRUE(slanted);
  EXPECT_NEAR((*slanted - Eigen::Vector3d(cx + 0.4 * k, cy + k, 0.3 * k)).norm(), 0.0, 1e-12);
}

TEST(WallPointOfBearing, RayAlongTheAxisNeverMeetsTheWall) {
  const Eigen::Isometry3d pose = WallLookingPose({0.0, 0.0, 0.0});
  EXPECT_FALSE(WallPointOfBearing(pose, Eigen::Vector3d::UnitX(), kRadius));
}

TEST(SurfaceCoordinates, RoundTripAndWrapAroundTheReference) {
  const double reference = M_PI / 2.0;
  const SurfacePoint facing = ToSurface({0.0, kRadius, 1.5}, kRadius, reference);
  EXPECT_NEAR(facing.h, 1.5, 1e-15);
  EXPECT_NEAR(facing.rho, 0.0, 1e-15);
  // phi = -3 pi / 4 lies -5 pi / 4 from the reference, which wraps to +3 pi / 4.
  const Eigen::Vector3d behind(kRadius * std::cos(-0.75 * M_PI), kRadius * std::sin(-0.75 * M_PI),
                               0.0);
  const SurfacePoint wrapped = ToSurface(behind, kRadius, reference);
  EXPECT_NEAR(wrapped.rho, kRadius * 0.75 * M_PI, 1e-12);
  EXPECT_NEAR((FromSurface(wrapped, kRadius, reference) - behind).norm(), 0.0, 1e-12);
}

TEST(TrackStatistics, ErrorFromSumsEqualsTheDirectSum) {
  TrackStatistics s;
  const std::vector<SurfacePoint> points = {{1.0, 0.1}, {1.2, 0.3}, {0.9, -0.2}};
  for (const SurfacePoint& p : points) s.Add(p);
  const SurfacePoint estimate{1.05, 0.02};
  double direct = 0.0;
  for (const SurfacePoint& p : points) {
    direct += std::pow(estimate.h - p.h, 2) + std::pow(estimate.rho - p.rho, 2);  // eq. 43
  }
  EXPECT_NEAR(s.Error(estimate), direct, 1e-12);  // eq. 44
  s.Remove(points[1]);
  EXPECT_EQ(s.n, 2.0);
  EXPECT_NEAR(s.Mean().h, 0.95, 1e-12);
}

}  // namespace
}  // namespace pipescope
