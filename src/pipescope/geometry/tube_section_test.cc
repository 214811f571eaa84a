// A bending tube section (a torus segment): its arc against the circle's closed form, and the
// ray-wall intersection against the torus written with its centre explicitly.
#include "pipescope/geometry/tube_section.h"

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace pipescope {
namespace {

// A section bending about the x axis: it leaves the origin along z and turns towards +y with a
// bend radius of `bend` metres.
TubeSection Bending(double bend, double radius) {
  TubeSection section;
  section.axis = Eigen::Vector3d::UnitZ();
  section.curvature = Eigen::Vector3d(0.0, 1.0 / bend, 0.0);
  section.log_radius = std::log(radius);
  return section;
}

// The distance of a point from the wall of a torus with centre c, the circle in the y-z plane of
// radius `bend`, written with the centre (what the section's form avoids).
double TorusWallDistance(const Eigen::Vector3d& point, double bend, double radius) {
  const Eigen::Vector3d centre(0.0, bend, 0.0);
  const Eigen::Vector3d q = point - centre;
  const double in_plane = std::hypot(q.y(), q.z());
  return std::hypot(in_plane - bend, q.x()) - radius;
}

TEST(TubeSection, ArcFollowsTheCircle) {
  const double bend = 0.5;
  const TubeSection section = Bending(bend, 0.1);
  const double quarter = M_PI / 2.0 * bend;
  EXPECT_LT((section.CentrelinePoint(quarter) - Eigen::Vector3d(0, bend, bend)).norm(), 1e-12);
  EXPECT_LT((section.TangentAt(quarter) - Eigen::Vector3d::UnitY()).norm(), 1e-12);
  EXPECT_LT((section.CurvatureAt(quarter) - Eigen::Vector3d(0, 0, -1.0 / bend)).norm(), 1e-12);
  // A point across the arc at s lies at arc coordinate s.
  for (double s : {-0.2, 0.0, 0.1, 0.4, 0.7}) {
    const Eigen::Vector3d across = section.CentrelinePoint(s) +
                                   0.05 * section.CurvatureAt(s).normalized() +
                                   0.03 * Eigen::Vector3d::UnitX();
    EXPECT_NEAR(section.ArcCoordinate(across), s, 1e-12) << s;
  }
}

TEST(TubeSection, StraightLimitIsTheCylinder) {
  TubeSection straight;
  straight.curvature = Eigen::Vector3d(0.0, 1e-12, 0.0);
  EXPECT_NEAR(straight.ArcCoordinate(Eigen::Vector3d(0.02, 0.03, 0.4)), 0.4, 1e-9);
  EXPECT_LT((straight.CentrelinePoint(0.4) - Eigen::Vector3d(0, 0, 0.4)).norm(), 1e-9);
  const Eigen::Vector3d offset(0.02, -0.05, 0.3);
  EXPECT_NEAR(SquaredDistanceFromCentreline<double>(offset, straight.axis, Eigen::Vector3d::Zero()),
              0.02 * 0.02 + 0.05 * 0.05, 1e-15);
}

TEST(TubeSection, RayMeetsTheTorusWall) {
  const double bend = 0.5, radius = 0.1;
  const TubeSection section = Bending(bend, radius);
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int checked = 0;
  for (int k = 0; k < 200; ++k) {
    // Origins inside the tube near its start, rays into every direction ahead.
    const Eigen::Vector3d origin(0.05 * unit(random), 0.05 * unit(random), 0.02 * unit(random));
    const Eigen::Vector3d direction =
        Eigen::Vector3d(unit(random), unit(random), 0.3 + std::abs(unit(random))).normalized();
    double alpha = 0.0;
    if (!IntersectRayWithTubeSection<double>(origin, direction, section.start, section.axis,
                                             section.curvature, radius, &alpha)) {
      continue;
    }
    const Eigen::Vector3d point = origin + alpha * direction;
    EXPECT_NEAR(TorusWallDistance(point, bend, radius), 0.0, 1e-10);
    // The first crossing: every point of the ray before it is inside.
    for (int i = 1; i < 50; ++i) {
      EXPECT_LT(TorusWallDistance(origin + alpha * i / 50.0 * direction, bend, radius), 1e-12);
    }
    ++checked;
  }
  EXPECT_GT(checked, 150);
}

TEST(TubeSection, IntersectionDerivativesMatchFiniteDifferences) {
  using Jet = ceres::Jet<double, 3>;
  const double radius = 0.1;
  const Eigen::Vector3d origin(0.01, -0.02, 0.0),
      direction = Eigen::Vector3d(0.3, 0.5, 1.0).normalized();
  // The derivative by the curvature's two components and the radius, at a bend and at none.
  for (double k : {0.0, 2.0}) {
    auto alpha_at = [&](const Eigen::Vector3d& curvature, double r) {
      double alpha = 0.0;
      EXPECT_TRUE(IntersectRayWithTubeSection<double>(origin, direction, Eigen::Vector3d::Zero(),
                                                      Eigen::Vector3d::UnitZ(), curvature, r,
                                                      &alpha));
      return alpha;
    };
    const Eigen::Matrix<Jet, 3, 1> curvature(Jet(0.0, 0), Jet(k) + Jet(0.0, 1), Jet(0.0));
    Jet alpha;
    ASSERT_TRUE(IntersectRayWithTubeSection<Jet>(
        origin.cast<Jet>(), direction.cast<Jet>(), Eigen::Matrix<Jet, 3, 1>::Zero(),
        Eigen::Vector3d::UnitZ().cast<Jet>(), curvature, Jet(radius) + Jet(0.0, 2), &alpha));
    const double h = 1e-6;
    const double d_kx = (alpha_at({h, k, 0}, radius) - alpha_at({-h, k, 0}, radius)) / (2 * h);
    const double d_ky =
        (alpha_at({0, k + h, 0}, radius) - alpha_at({0, k - h, 0}, radius)) / (2 * h);
    const double d_r =
        (alpha_at({0, k, 0}, radius + h) - alpha_at({0, k, 0}, radius - h)) / (2 * h);
    EXPECT_NEAR(alpha.a, alpha_at({0, k, 0}, radius), 1e-12);
    EXPECT_NEAR(alpha.v[0], d_kx, 1e-6) << k;
    EXPECT_NEAR(alpha.v[1], d_ky, 1e-6) << k;
    EXPECT_NEAR(alpha.v[2], d_r, 1e-6) << k;
  }
}

TEST(TubeSection, JunctionAfterABendIsTheNextStart) {
  const TubeSection before = Bending(0.5, 0.1);
  TubeSection after;
  after.start = before.CentrelinePoint(0.3);
  after.axis = before.TangentAt(0.3);
  EXPECT_LT((SectionJunction(before, after) - after.start).norm(), 1e-15);
}

}  // namespace
}  // namespace pipescope
