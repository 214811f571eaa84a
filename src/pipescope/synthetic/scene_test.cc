#include "pipescope/synthetic/scene.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <iostream>
#include <numbers>
#include <random>
#include <stdexcept>
#include <vector>

namespace pipescope {
namespace {

using Eigen::Vector3d;

constexpr double kPi = std::numbers::pi;
constexpr double kRadius = 0.2;
constexpr double kBendRadius = 0.6;

Vector3d Direction(double x, double y, double z) { return Vector3d(x, y, z).normalized(); }

double Wrap(double phi) { return phi < 0 ? phi + 2 * kPi : phi; }

// An oracle independent of Scene's internals, from the public section fields only: the foot of
// a point on a section's centreline (arc length h) and its distance from it.
struct Foot {
  double h;
  double radial;
};

Foot FootOf(const PipeSection& section, const Vector3d& point) {
  if (section.type == SectionType::kStraight) {
    const Vector3d local = point - section.start;
    const double h = local.dot(section.start_direction);
    return {h, (local - h * section.start_direction).norm()};
  }
  const Vector3d local = point - section.bend_center;
  const double z = local.dot(section.bend_axis);
  const Vector3d in_plane = local - z * section.bend_axis;
  const Vector3d u0 = (section.start - section.bend_center) / section.bend_radius;
  const double theta = std::atan2(in_plane.dot(section.start_direction), in_plane.dot(u0));
  return {section.bend_radius * theta, std::hypot(in_plane.norm() - section.bend_radius, z)};
}

bool InRange(const PipeSection& section, double h) {
  return h >= -Scene::kJointOverlap && h <= section.length + Scene::kJointOverlap;
}

bool OracleInside(const Scene& scene, const Vector3d& point, double margin) {
  for (const PipeSection& section : scene.sections()) {
    const Foot foot = FootOf(section, point);
    if (InRange(section, foot.h) && foot.radial < section.radius + margin) return true;
  }
  return false;
}

// Distance of the point from the nearest wall whose foot lies within its section.
double OracleWallDistance(const Scene& scene, const Vector3d& point) {
  double best = INFINITY;
  for (const PipeSection& section : scene.sections()) {
    const Foot foot = FootOf(section, point);
    if (InRange(section, foot.h)) best = std::min(best, std::abs(foot.radial - section.radius));
  }
  return best;
}

// Checks a hit against the oracle: it lies on a wall, on no other section's interior, and the
// ray stays inside the union until it.
void ExpectHitIsUnionExit(const Scene& scene, const Ray& ray, const WallHit& hit) {
  EXPECT_LT(OracleWallDistance(scene, hit.point), 1e-9) << hit.point.transpose();
  EXPECT_LT((hit.point - (ray.origin + hit.distance * ray.direction)).norm(), 1e-12);
  for (int i = 0; i < static_cast<int>(scene.sections().size()); ++i) {
    if (i == hit.section) continue;
    const PipeSection& other = scene.sections()[i];
    const Foot foot = FootOf(other, hit.point);
    EXPECT_FALSE(InRange(other, foot.h) && foot.radial < other.radius - 1e-8)
        << "hit of section " << hit.section << " lies inside section " << i;
  }
  constexpr int kSamples = 200;
  for (int k = 0; k < kSamples; ++k) {
    const Vector3d sample = ray.origin + (hit.distance * k / kSamples) * ray.direction;
    EXPECT_TRUE(OracleInside(scene, sample, 1e-9)) << "left the pipe before the hit at " << k;
  }
}

// A straight pipe along Z from z = -1 to z = 3.
Scene StraightPipe() {
  Scene scene;
  scene.AddStraight(Vector3d(0, 0, -1), Vector3d(0, 0, 3), kRadius);
  return scene;
}

// Straight along Z to the origin, a 90 degree bend towards +X, straight along +X.
Scene StraightBendStraight() {
  Scene scene;
  scene.AddStraight(Vector3d(0, 0, -1), Vector3d(0, 0, 0), kRadius);
  scene.AddBend(Vector3d(0, 0, 0), Vector3d::UnitZ(), Vector3d::UnitX(), kBendRadius, kPi / 2,
                kRadius);
  const PipeSection& bend = scene.sections()[1];
  scene.AddStraight(bend.EndPoint(), bend.EndPoint() + 2 * bend.EndDirection(), kRadius);
  return scene;
}

// A through run along Z through the origin and a branch along +X from the origin.
Scene Tee() {
  Scene scene;
  scene.AddStraight(Vector3d(0, 0, -2), Vector3d(0, 0, 2), kRadius);
  scene.AddTee("T1", Vector3d::Zero());
  scene.AddStraight(Vector3d::Zero(), Vector3d(2, 0, 0), kRadius);
  return scene;
}

// The fiberglass-network shape: a square loop of four T's in the X-Z plane with dead-end stubs.
Scene SquareLoop(double side, double radius) {
  Scene scene;
  const Vector3d t1(0, 0, 0), t2(0, 0, side), t3(side, 0, side), t4(side, 0, 0);
  scene.AddStraight(Vector3d(0, 0, -2), t1, radius);
  scene.AddTee("T1", t1);
  scene.AddStraight(t1, t2, radius);
  scene.AddTee("T2", t2);
  scene.AddStraight(t2, t2 + Vector3d(0, 0, 1), radius);
  scene.AddStraight(t2, t3, radius);
  scene.AddTee("T3", t3);
  scene.AddStraight(t3, t3 + Vector3d(1, 0, 0), radius);
  scene.AddStraight(t3, t4, radius);
  scene.AddTee("T4", t4);
  scene.AddStraight(t4, t1, radius);
  scene.AddStraight(t4, t4 + Vector3d(0, 0, -2), radius);
  return scene;
}

TEST(SceneStraight, RaysFromAxisHitAtClosedFormDistance) {
  const Scene scene = StraightPipe();
  const Vector3d origin(0, 0, 0.5);
  for (const double elevation : {0.1, 0.3, 0.7, kPi / 2, 2.0, 2.9}) {
    for (const double azimuth : {0.0, 1.0, 2.5, 4.0, 5.9}) {
      const Ray ray{origin, Vector3d(std::sin(elevation) * std::cos(azimuth),
                                     std::sin(elevation) * std::sin(azimuth), std::cos(elevation))};
      const auto hit = scene.Intersect(ray);
      ASSERT_TRUE(hit.has_value()) << elevation << " " << azimuth;
      const double distance = kRadius / std::sin(elevation);
      const double z = 0.5 + distance * std::cos(elevation);
      EXPECT_NEAR(hit->distance, distance, 1e-13);
      EXPECT_LT((hit->point - Vector3d(kRadius * std::cos(azimuth), kRadius * std::sin(azimuth), z))
                    .norm(),
                1e-13);
      EXPECT_LT((hit->normal - Vector3d(-std::cos(azimuth), -std::sin(azimuth), 0)).norm(), 1e-12);
      EXPECT_EQ(hit->section, 0);
      EXPECT_NEAR(hit->h_m, z + 1, 1e-13);
      EXPECT_NEAR(hit->s_m, kRadius * azimuth, 1e-12);
    }
  }
}

// The renderer's fan of rays from one origin agrees with Intersect(): from inside a straight
// pipe (its fast path), near either end, on the axis, and from outside and in a network (where
// it defers to Intersect()).
TEST(SceneRayFan, AgreesWithIntersect) {
  const Scene straight = StraightPipe();
  const Scene network = SquareLoop(3.0, kRadius);
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  struct Case {
    const Scene* scene;
    Vector3d origin;
  };
  const Case cases[] = {
      {&straight, Vector3d(0, 0, 0.5)},      {&straight, Vector3d(0.05, -0.1, 1.2)},
      {&straight, Vector3d(0.1, 0.1, -0.9)}, {&straight, Vector3d(0, 0, 2.95)},
      {&straight, Vector3d(0.3, 0, 0.5)},    {&network, Vector3d(0.02, 0, 1.0)}};
  for (const Case& c : cases) {
    const Scene::RayFan fan(*c.scene, c.origin);
    int hits = 0;
    for (int i = 0; i < 2000; ++i) {
      Vector3d d = Direction(normal(rng), normal(rng), 3 * normal(rng));
      if (i == 0) d = Vector3d::UnitZ();  // along the axis: out through the open end
      WallHit fan_hit;
      const bool fan_found = fan.Intersect(d, &fan_hit);
      const auto hit = c.scene->Intersect({c.origin, d});
      ASSERT_EQ(fan_found, hit.has_value()) << c.origin.transpose() << " / " << d.transpose();
      if (!hit) continue;
      ++hits;
      EXPECT_NEAR(fan_hit.distance, hit->distance, 1e-13);
      EXPECT_LT((fan_hit.point - hit->point).norm(), 1e-13);
      EXPECT_LT((fan_hit.normal - hit->normal).norm(), 1e-12);
      EXPECT_EQ(fan_hit.section, hit->section);
      EXPECT_NEAR(fan_hit.h_m, hit->h_m, 1e-13);
      EXPECT_NEAR(fan_hit.s_m, hit->s_m, 1e-12);
    }
    EXPECT_GT(hits, 100) << c.origin.transpose();
  }
}

TEST(SceneStraight, RaysAlongTheAxisEscapeThroughTheOpenEnds) {
  const Scene scene = StraightPipe();
  EXPECT_FALSE(scene.Intersect({Vector3d(0, 0, 0.5), Vector3d::UnitZ()}).has_value());
  EXPECT_FALSE(scene.Intersect({Vector3d(0, 0, 0.5), -Vector3d::UnitZ()}).has_value());
  EXPECT_FALSE(scene.Intersect({Vector3d(0.1, -0.05, 0.5), Vector3d::UnitZ()}).has_value());
  // A ray 1 mrad off the axis reaches the wall only 200 m away, past the end.
  EXPECT_FALSE(scene.Intersect({Vector3d(0, 0, 0.5), Direction(1e-3, 0, 1)}).has_value());
}

TEST(SceneStraight, NearlyAxialRaysAreAccurate) {
  Scene scene;
  scene.AddStraight(Vector3d(0, 0, 0), Vector3d(0, 0, 1e7), kRadius);
  for (const double angle : {1e-2, 1e-4, 1e-6}) {
    const Ray ray{Vector3d(0, 0, 1), Vector3d(0, std::sin(angle), std::cos(angle))};
    const auto hit = scene.Intersect(ray);
    ASSERT_TRUE(hit.has_value()) << angle;
    const double distance = kRadius / std::sin(angle);
    EXPECT_NEAR(hit->distance / distance, 1.0, 1e-14) << angle;
    EXPECT_NEAR(hit->point.y(), kRadius, 1e-12);
    EXPECT_NEAR(hit->s_m, kRadius * kPi / 2, 1e-12);
  }
}

TEST(SceneStraight, RayFromAnOffAxisOrigin) {
  const Scene scene = StraightPipe();
  const Vector3d origin(0.05, -0.08, 0.4);
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  for (int trial = 0; trial < 50; ++trial) {
    const Vector3d d = Direction(normal(rng), normal(rng), 0.3 * normal(rng));
    // Closed form: the line in the cross-section meets the circle x^2 + y^2 = r^2.
    const double a = d.x() * d.x() + d.y() * d.y();
    const double b = origin.x() * d.x() + origin.y() * d.y();
    const double c = origin.x() * origin.x() + origin.y() * origin.y() - kRadius * kRadius;
    const double t = (-b + std::sqrt(b * b - a * c)) / a;
    const Vector3d expected = origin + t * d;
    const auto hit = scene.Intersect({origin, d});
    if (expected.z() < -1 || expected.z() > 3) {
      EXPECT_FALSE(hit.has_value());
      continue;
    }
    ASSERT_TRUE(hit.has_value());
    EXPECT_NEAR(hit->distance, t, 1e-13);
    EXPECT_NEAR(hit->h_m, expected.z() + 1, 1e-13);
    EXPECT_NEAR(hit->s_m, kRadius * Wrap(std::atan2(expected.y(), expected.x())), 1e-12);
    EXPECT_NEAR(hit->normal.dot(-Vector3d(expected.x(), expected.y(), 0) / kRadius), 1.0, 1e-12);
  }
}

TEST(SceneStraight, ReferenceDirections) {
  Scene scene;
  scene.AddStraight(Vector3d::Zero(), Vector3d(0, 0, 1), kRadius);
  scene.AddStraight(Vector3d::Zero(), Vector3d(1, 0, 0), kRadius);
  scene.AddStraight(Vector3d::Zero(), Vector3d(1, 0, 1), kRadius);
  scene.AddStraight(Vector3d::Zero(), Vector3d(0, 0, 1), kRadius, Vector3d(0, 2, 0.5));
  EXPECT_LT((scene.sections()[0].reference - Vector3d::UnitX()).norm(), 1e-15);
  EXPECT_LT((scene.sections()[1].reference - Vector3d::UnitY()).norm(), 1e-15);
  EXPECT_LT((scene.sections()[2].reference - Direction(1, 0, -1)).norm(), 1e-15);
  EXPECT_LT((scene.sections()[3].reference - Vector3d::UnitY()).norm(), 1e-15);
  EXPECT_NEAR(scene.sections()[2].length, std::sqrt(2.0), 1e-15);

  // With reference +Y, phi = 90 deg is Z x Y = -X, so +X is at 270 deg.
  Scene custom;
  custom.AddStraight(Vector3d::Zero(), Vector3d(0, 0, 1), kRadius, Vector3d::UnitY());
  const auto hit = custom.Intersect({Vector3d(0, 0, 0.5), Vector3d::UnitX()});
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->s_m, kRadius * 1.5 * kPi, 1e-12);
}

TEST(SceneStraight, Contains) {
  const Scene scene = StraightPipe();
  EXPECT_TRUE(scene.Contains(Vector3d(0, 0, 0)));
  EXPECT_TRUE(scene.Contains(Vector3d(0.199, 0, 2.9)));
  EXPECT_TRUE(scene.Contains(Vector3d(0, -0.199, -0.99)));
  EXPECT_FALSE(scene.Contains(Vector3d(0.201, 0, 1)));
  EXPECT_FALSE(scene.Contains(Vector3d(0.15, 0.15, 1)));  // Radius 0.212.
  EXPECT_FALSE(scene.Contains(Vector3d(0, 0, 3.01)));
  EXPECT_FALSE(scene.Contains(Vector3d(0, 0, -1.01)));
}

TEST(SceneBend, GeometryAndFrames) {
  const Scene scene = StraightBendStraight();
  const PipeSection& bend = scene.sections()[1];
  EXPECT_EQ(bend.type, SectionType::kBend);
  EXPECT_LT((bend.bend_center - Vector3d(kBendRadius, 0, 0)).norm(), 1e-15);
  EXPECT_LT((bend.bend_axis - Vector3d::UnitY()).norm(), 1e-15);
  EXPECT_NEAR(bend.length, kBendRadius * kPi / 2, 1e-15);
  EXPECT_LT((bend.EndPoint() - Vector3d(kBendRadius, 0, kBendRadius)).norm(), 1e-15);
  EXPECT_LT((bend.EndDirection() - Vector3d::UnitX()).norm(), 1e-15);
  for (const double theta : {0.0, 0.4, 1.2, kPi / 2}) {
    Vector3d point, tangent, reference;
    bend.FrameAt(kBendRadius * theta, &point, &tangent, &reference);
    EXPECT_LT(
        (point - Vector3d(kBendRadius * (1 - std::cos(theta)), 0, kBendRadius * std::sin(theta)))
            .norm(),
        1e-15);
    EXPECT_LT((tangent - Vector3d(std::sin(theta), 0, std::cos(theta))).norm(), 1e-15);
    // The start reference +X (towards the bend centre) turns with the arc.
    EXPECT_LT((reference - Vector3d(std::cos(theta), 0, -std::sin(theta))).norm(), 1e-15);
  }
}

TEST(SceneBend, RaysFromTheCentrelineHitAtClosedFormDistance) {
  Scene scene;
  scene.AddBend(Vector3d::Zero(), Vector3d::UnitZ(), Vector3d::UnitX(), kBendRadius, kPi / 2,
                kRadius);
  const PipeSection& bend = scene.sections()[0];
  const Vector3d center = bend.bend_center;
  int checked = 0;
  for (const double theta : {0.3, 0.7, 1.1}) {
    Vector3d point, tangent, inward;
    bend.FrameAt(kBendRadius * theta, &point, &tangent, &inward);
    // Across the tube: distance r, phi = 90 deg at +Y (tangent x inward), 270 deg at -Y.
    for (const double sign : {1.0, -1.0}) {
      const auto hit = scene.Intersect({point, sign * Vector3d::UnitY()});
      ASSERT_TRUE(hit.has_value());
      EXPECT_NEAR(hit->distance, kRadius, 1e-13);
      EXPECT_NEAR(hit->h_m, kBendRadius * theta, 1e-13);
      EXPECT_NEAR(hit->s_m, kRadius * (sign > 0 ? 0.5 : 1.5) * kPi, 1e-12);
      EXPECT_LT((hit->normal + sign * Vector3d::UnitY()).norm(), 1e-12);
    }
    // In the bend plane at angle beta from the tangent: the line meets the inner circle
    // (R - r) or the outer one (R + r) about the bend centre.
    for (double beta = -1.4; beta <= 1.4; beta += 0.1) {
      const Vector3d d = std::cos(beta) * tangent + std::sin(beta) * inward;
      const double b = (point - center).dot(d);
      const double inner_disc =
          b * b - (kBendRadius * kBendRadius - (kBendRadius - kRadius) * (kBendRadius - kRadius));
      double t = -b + std::sqrt(b * b + (kBendRadius + kRadius) * (kBendRadius + kRadius) -
                                kBendRadius * kBendRadius);
      if (inner_disc >= 0 && -b - std::sqrt(inner_disc) > 0) t = -b - std::sqrt(inner_disc);
      const Vector3d expected = point + t * d;
      const double angle = std::atan2((expected - center).dot(Vector3d::UnitZ()),
                                      (expected - center).dot(-Vector3d::UnitX()));
      if (angle < 0 || angle > kPi / 2) continue;  // Leaves through an end.
      const auto hit = scene.Intersect({point, d});
      ASSERT_TRUE(hit.has_value()) << theta << " " << beta;
      EXPECT_NEAR(hit->distance, t, 1e-12) << theta << " " << beta;
      EXPECT_NEAR(hit->h_m, kBendRadius * angle, 1e-12);
      EXPECT_NEAR(std::remainder(hit->s_m, kRadius * kPi), 0, 1e-12);  // phi = 0 or pi.
      ++checked;
    }
  }
  EXPECT_GT(checked, 40);
}

// A bend of the given angle in a tilted plane: the frame must not matter.
Scene TiltedBend(double angle) {
  const Vector3d start_direction = Direction(0.3, -0.2, 1);
  Vector3d turn(1, 0.5, 0);
  turn = (turn - turn.dot(start_direction) * start_direction).normalized();
  Scene scene;
  scene.AddBend(Vector3d(1, 2, 3), start_direction, turn, kBendRadius, angle, kRadius);
  return scene;
}

class SceneBendAngle : public testing::TestWithParam<double> {};

TEST_P(SceneBendAngle, HitsLieOnTheTorusAndRaysStayInside) {
  const Scene scene = TiltedBend(GetParam());
  const PipeSection& bend = scene.sections()[0];
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uniform(-1, 1);
  int hits = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    Vector3d point, tangent, reference;
    bend.FrameAt(bend.length * (0.5 + 0.45 * uniform(rng)), &point, &tangent, &reference);
    const Vector3d origin =
        point + 0.5 * kRadius * Vector3d(uniform(rng), uniform(rng), uniform(rng)) / std::sqrt(3.0);
    const Ray ray{origin, Direction(uniform(rng), uniform(rng), uniform(rng))};
    const auto hit = scene.Intersect(ray);
    if (!hit) {
      // It must leave through an end disc: outside the angular range, radially inside.
      double t = 0;
      while (OracleInside(scene, ray.origin + t * ray.direction, 0)) t += 1e-4;
      const Foot foot = FootOf(bend, ray.origin + t * ray.direction);
      EXPECT_LT(foot.radial, kRadius + 1e-3);
      EXPECT_TRUE(foot.h < 1e-3 || foot.h > bend.length - 1e-3) << foot.h;
      continue;
    }
    ++hits;
    // The implicit torus equation (|p|^2 + R^2 - r^2)^2 = 4 R^2 (|p|^2 - (p.axis)^2), scaled.
    const Vector3d p = hit->point - bend.bend_center;
    const double z = p.dot(bend.bend_axis);
    const double lhs = p.squaredNorm() + kBendRadius * kBendRadius - kRadius * kRadius;
    EXPECT_NEAR(lhs * lhs, 4 * kBendRadius * kBendRadius * (p.squaredNorm() - z * z), 1e-12);
    const Foot foot = FootOf(bend, hit->point);
    EXPECT_NEAR(foot.radial, kRadius, 1e-12);
    EXPECT_NEAR(hit->h_m, foot.h, 1e-12);
    Vector3d foot_point, foot_tangent, foot_reference;
    bend.FrameAt(foot.h, &foot_point, &foot_tangent, &foot_reference);
    EXPECT_LT((hit->normal - (foot_point - hit->point) / kRadius).norm(), 1e-11);
    const Vector3d radial = hit->point - foot_point;
    const double phi = Wrap(
        std::atan2(radial.dot(foot_tangent.cross(foot_reference)), radial.dot(foot_reference)));
    EXPECT_NEAR(std::remainder(hit->s_m - kRadius * phi, 2 * kPi * kRadius), 0, 1e-11);
    ExpectHitIsUnionExit(scene, ray, *hit);
  }
  EXPECT_GT(hits, 500);
}

INSTANTIATE_TEST_SUITE_P(Angles, SceneBendAngle, testing::Values(0.3, kPi / 2, 0.8 * kPi, kPi));

TEST(SceneBend, GrazingRaysStayOnTheWall) {
  Scene scene;
  scene.AddBend(Vector3d::Zero(), Vector3d::UnitZ(), Vector3d::UnitX(), kBendRadius, kPi / 2,
                kRadius);
  const PipeSection& bend = scene.sections()[0];
  // From a point just inside the outer wall, rays nearly tangent to the wall.
  Vector3d point, tangent, inward;
  bend.FrameAt(0.2 * bend.length, &point, &tangent, &inward);
  const Vector3d origin = point - (kRadius - 1e-6) * inward;
  for (const double tilt : {1e-2, 1e-3, 1e-4, 1e-5}) {
    const Ray ray{origin, (tangent + tilt * inward + 0.3 * Vector3d::UnitY()).normalized()};
    const auto hit = scene.Intersect(ray);
    ASSERT_TRUE(hit.has_value()) << tilt;
    EXPECT_NEAR(FootOf(bend, hit->point).radial, kRadius, 1e-12) << tilt;
    ExpectHitIsUnionExit(scene, ray, *hit);
  }
}

TEST(SceneTee, RayIntoTheBranchHitsTheBranchWall) {
  const Scene scene = Tee();
  ASSERT_EQ(scene.junctions().size(), 1u);
  EXPECT_EQ(scene.junctions()[0].name, "T1");
  ASSERT_EQ(scene.entries().size(), 3u);
  EXPECT_TRUE(scene.entries()[1].is_tee);

  // Along the branch axis the ray leaves through the branch's open end.
  EXPECT_FALSE(scene.Intersect({Vector3d::Zero(), Vector3d::UnitX()}).has_value());
  // Into the branch: through the main pipe's opening to the branch wall at z = r.
  auto hit = scene.Intersect({Vector3d::Zero(), Direction(1, 0, 0.2)});
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(hit->section, 1);
  EXPECT_NEAR(hit->distance, std::sqrt(1 + 0.04), 1e-13);
  EXPECT_LT((hit->point - Vector3d(1, 0, kRadius)).norm(), 1e-13);
  EXPECT_LT((hit->normal - Vector3d(0, 0, -1)).norm(), 1e-12);
  EXPECT_NEAR(hit->h_m, 1, 1e-13);
  // Through the opening at a steeper angle: the main wall at x = r, z = 0.3 is outside it.
  hit = scene.Intersect({Vector3d::Zero(), Direction(1, 0, 1.5)});
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(hit->section, 0);
  EXPECT_LT((hit->point - Vector3d(kRadius, 0, 0.3)).norm(), 1e-13);
  // The far side of the main pipe is solid wall.
  hit = scene.Intersect({Vector3d::Zero(), Direction(-1, 0, 0.2)});
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(hit->section, 0);
  EXPECT_LT((hit->point - Vector3d(-kRadius, 0, 0.04)).norm(), 1e-13);
  EXPECT_LT((hit->normal - Vector3d(1, 0, 0)).norm(), 1e-12);
}

TEST(SceneTee, RandomRaysLeaveTheUnionAtItsBoundary) {
  const Scene scene = Tee();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uniform(-1, 1);
  int hits = 0, branch_hits = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    Vector3d origin(uniform(rng) * kRadius, uniform(rng) * kRadius, uniform(rng) * kRadius);
    if (!OracleInside(scene, origin, -1e-3)) continue;
    const Ray ray{origin, Direction(uniform(rng), uniform(rng), uniform(rng))};
    const auto hit = scene.Intersect(ray);
    if (!hit) continue;
    ++hits;
    branch_hits += hit->section == 1;
    ExpectHitIsUnionExit(scene, ray, *hit);
  }
  EXPECT_GT(hits, 1000);
  EXPECT_GT(branch_hits, 200);
}

TEST(SceneTee, Contains) {
  const Scene scene = Tee();
  EXPECT_TRUE(scene.Contains(Vector3d::Zero()));
  EXPECT_TRUE(scene.Contains(Vector3d(0.19, 0, 1)));
  EXPECT_TRUE(scene.Contains(Vector3d(1, 0.19, 0)));
  EXPECT_TRUE(scene.Contains(Vector3d(0.25, 0, 0.15)));  // Inside the branch only.
  EXPECT_FALSE(scene.Contains(Vector3d(0.21, 0, 1)));
  EXPECT_FALSE(scene.Contains(Vector3d(1, 0, 0.21)));
  EXPECT_FALSE(scene.Contains(Vector3d(1, 0.15, 0.15)));
  EXPECT_FALSE(scene.Contains(Vector3d(-0.21, 0, 0)));
  EXPECT_FALSE(scene.Contains(Vector3d(0, 0.21, 0)));
  EXPECT_FALSE(scene.Contains(Vector3d(2.01, 0, 0)));
}

// Rays from `origin` aimed at wall points spread densely around and across a seam (a circle of
// the wall at `center` with axis `tangent`): none may escape through a crack.
void ExpectSeamIsWatertight(const Scene& scene, const Vector3d& origin, const Vector3d& center,
                            const Vector3d& tangent, double radius) {
  const Vector3d x = tangent.unitOrthogonal(), y = tangent.cross(x);
  int rays = 0;
  for (int k = -20; k <= 20; ++k) {
    // Offsets across the seam from far (1 mm) to below rounding (1e-15 m).
    const double offset =
        k == 0 ? 0 : std::copysign(std::pow(10.0, -3 - 12 * (20 - std::abs(k)) / 19.0), k);
    for (int a = 0; a < 360; ++a) {
      const double phi = 2 * kPi * a / 360 + 1e-3 * k;
      const Vector3d target =
          center + offset * tangent + radius * (std::cos(phi) * x + std::sin(phi) * y);
      const Ray ray{origin, (target - origin).normalized()};
      const auto hit = scene.Intersect(ray);
      ASSERT_TRUE(hit.has_value()) << "crack at offset " << offset << " phi " << phi;
      EXPECT_LT(OracleWallDistance(scene, hit->point), 1e-9);
      ++rays;
    }
  }
  EXPECT_EQ(rays, 41 * 360);
}

TEST(SceneJoints, CollinearStraightsHaveNoCracks) {
  Scene scene;
  scene.AddStraight(Vector3d(0, 0, 0), Vector3d(0, 0, 1), kRadius);
  scene.AddStraight(Vector3d(0, 0, 1), Vector3d(0, 0, 2), kRadius);
  ExpectSeamIsWatertight(scene, Vector3d(0.03, -0.05, 0.3), Vector3d(0, 0, 1), Vector3d::UnitZ(),
                         kRadius);
  ExpectSeamIsWatertight(scene, Vector3d(0, 0, 1.7), Vector3d(0, 0, 1), Vector3d::UnitZ(), kRadius);
}

TEST(SceneJoints, StraightBendStraightHasNoCracks) {
  const Scene scene = StraightBendStraight();
  const PipeSection& bend = scene.sections()[1];
  ExpectSeamIsWatertight(scene, Vector3d(0.05, 0.02, -0.6), Vector3d::Zero(), Vector3d::UnitZ(),
                         kRadius);
  Vector3d point, tangent, reference;
  bend.FrameAt(0.5 * bend.length, &point, &tangent, &reference);
  ExpectSeamIsWatertight(scene, point, Vector3d::Zero(), Vector3d::UnitZ(), kRadius);
  ExpectSeamIsWatertight(scene, point, bend.EndPoint(), bend.EndDirection(), kRadius);
  ExpectSeamIsWatertight(scene, bend.EndPoint() + Vector3d(1.2, 0.03, 0), bend.EndPoint(),
                         bend.EndDirection(), kRadius);

  // Random rays from the bend check the whole union, both seams included.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> uniform(-1, 1);
  for (int trial = 0; trial < 1000; ++trial) {
    const Ray ray{point + 0.5 * kRadius * Vector3d(uniform(rng), uniform(rng), uniform(rng)),
                  Direction(uniform(rng), uniform(rng), uniform(rng))};
    const auto hit = scene.Intersect(ray);
    if (hit) ExpectHitIsUnionExit(scene, ray, *hit);
  }
}

TEST(SceneJoints, SquareLoopOfTees) {
  const Scene scene = SquareLoop(8.15, 0.2);
  ASSERT_EQ(scene.junctions().size(), 4u);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> uniform(-1, 1);
  int hits = 0;
  for (const auto& junction : scene.junctions()) {
    for (int trial = 0; trial < 500; ++trial) {
      const Vector3d origin =
          junction.center +
          0.15 * Vector3d(uniform(rng), uniform(rng), uniform(rng)) / std::sqrt(3.0);
      const Ray ray{origin, Direction(uniform(rng), 0.5 * uniform(rng), uniform(rng))};
      const auto hit = scene.Intersect(ray);
      if (!hit) continue;
      ++hits;
      ExpectHitIsUnionExit(scene, ray, *hit);
    }
  }
  EXPECT_GT(hits, 1500);
}

TEST(SceneValidation, RejectsDegenerateGeometry) {
  Scene scene;
  EXPECT_THROW(scene.AddStraight(Vector3d::Zero(), Vector3d::Zero(), kRadius),
               std::invalid_argument);
  EXPECT_THROW(scene.AddStraight(Vector3d::Zero(), Vector3d::UnitZ(), 0), std::invalid_argument);
  EXPECT_THROW(scene.AddStraight(Vector3d::Zero(), Vector3d::UnitZ(), kRadius, Vector3d::UnitZ()),
               std::invalid_argument);
  EXPECT_THROW(
      scene.AddBend(Vector3d::Zero(), Vector3d::UnitZ(), Vector3d::UnitX(), 0.1, 1, kRadius),
      std::invalid_argument);
  EXPECT_THROW(scene.AddBend(Vector3d::Zero(), Vector3d::UnitZ(), Vector3d::UnitX(), 1, 4, kRadius),
               std::invalid_argument);
  EXPECT_THROW(
      scene.AddBend(Vector3d::Zero(), Vector3d::UnitZ(), Direction(1, 0, 1), 1, 1, kRadius),
      std::invalid_argument);
  scene.AddTee("T1", Vector3d::Zero());
  EXPECT_THROW(scene.AddTee("T1", Vector3d::UnitX()), std::invalid_argument);
  EXPECT_TRUE(scene.sections().empty());
}

// Forward-looking camera rays over a 190 degree field of view, as the fisheye presets render.
}  // namespace
}  // namespace pipescope
