#include "pipescope/geometry/multiview_triangulation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "pipescope/geometry/sphere_relative_pose.h"

namespace pipescope {
namespace {

// A camera at `centre` looking along +Z of the world, turned by `angle_rad` about the axis
// `axis` (a crawler's pose in a pipe).
Eigen::Isometry3d CamFromWorld(const Eigen::Vector3d& centre, double angle_rad,
                               const Eigen::Vector3d& axis) {
  Eigen::Isometry3d world_from_cam = Eigen::Isometry3d::Identity();
  world_from_cam.linear() = Eigen::AngleAxisd(angle_rad, axis.normalized()).toRotationMatrix();
  world_from_cam.translation() = centre;
  return world_from_cam.inverse();
}

BearingObservation Observe(const Eigen::Isometry3d& cam_from_world, const Eigen::Vector3d& point) {
  return {cam_from_world, (cam_from_world * point).normalized()};
}

TEST(MultiviewTriangulation, RecoversAPointExactlyFromNoiseFreeBearingsBeyondNinetyDegrees) {
  // A wall point 0.2 m off the axis and 5 cm ahead of the first camera: from the later
  // cameras it lies behind the image plane (bearing z < 0), where a pinhole model has no
  // projection.
  const Eigen::Vector3d point(0.2, 0.0, 0.05);
  std::vector<BearingObservation> observations;
  for (int k = 0; k < 6; ++k) {
    const Eigen::Isometry3d cam_from_world = CamFromWorld(
        Eigen::Vector3d(0.001 * k, -0.002 * k, 0.02 * k), 0.01 * k, Eigen::Vector3d(0.3, 1.0, 0.1));
    observations.push_back(Observe(cam_from_world, point));
  }
  ASSERT_LT(observations.back().bearing.z(), 0.0);
  Eigen::Vector3d estimate;
  ASSERT_TRUE(TriangulateMidpoint(observations, &estimate));
  EXPECT_LT((estimate - point).norm(), 1e-12);
}

TEST(MultiviewTriangulation, TwoViewsGiveTheMidpointOfTheCommonPerpendicular) {
  // With two noisy rays the least-squares point is the midpoint of their closest points, which
  // TriangulateDepthsMidpoint (an independent two-view derivation) gives as depths.
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, 0.01);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Vector3d point(0.2 * std::cos(trial), 0.2 * std::sin(trial), 0.3 + 0.01 * trial);
    const Eigen::Isometry3d cam_i =
        CamFromWorld(Eigen::Vector3d::Zero(), 0.0, Eigen::Vector3d::UnitY());
    const Eigen::Isometry3d cam_j =
        CamFromWorld(Eigen::Vector3d(0.003, 0.001, 0.05), 0.02, Eigen::Vector3d(1.0, 0.5, 0.2));
    BearingObservation a = Observe(cam_i, point);
    BearingObservation b = Observe(cam_j, point);
    a.bearing = (a.bearing + Eigen::Vector3d(noise(rng), noise(rng), noise(rng))).normalized();
    b.bearing = (b.bearing + Eigen::Vector3d(noise(rng), noise(rng), noise(rng))).normalized();
    const Eigen::Isometry3d j_from_i = cam_j * cam_i.inverse();
    double depth_i, depth_j;
    ASSERT_TRUE(TriangulateDepthsMidpoint(j_from_i.linear(), j_from_i.translation(), a.bearing,
                                          b.bearing, &depth_i, &depth_j));
    const Eigen::Vector3d closest_i = cam_i.inverse() * (depth_i * a.bearing);
    const Eigen::Vector3d closest_j = cam_j.inverse() * (depth_j * b.bearing);
    Eigen::Vector3d estimate;
    ASSERT_TRUE(TriangulateMidpoint({a, b}, &estimate));
    EXPECT_LT((estimate - 0.5 * (closest_i + closest_j)).norm(), 1e-10) << "trial " << trial;
  }
}

TEST(MultiviewTriangulation, RefusesParallelRaysAndPointsBehindACamera) {
  const Eigen::Vector3d point(0.2, 0.0, 1.0);
  const Eigen::Isometry3d cam_i =
      CamFromWorld(Eigen::Vector3d::Zero(), 0.0, Eigen::Vector3d::UnitY());
  const Eigen::Isometry3d cam_j =
      CamFromWorld(Eigen::Vector3d(0.0, 0.0, 0.05), 0.0, Eigen::Vector3d::UnitY());
  // The same bearing from both cameras: parallel rays, no depth.
  BearingObservation a = Observe(cam_i, point);
  BearingObservation b{cam_j, a.bearing};
  Eigen::Vector3d estimate;
  EXPECT_FALSE(TriangulateMidpoint({a, b}, &estimate));
  EXPECT_FALSE(TriangulateMidpoint({a}, &estimate));
  // Rays that meet behind the cameras.
  const Eigen::Vector3d behind(0.2, 0.0, -1.0);
  BearingObservation c = Observe(cam_i, behind);
  BearingObservation d = Observe(cam_j, behind);
  c.bearing = -c.bearing;
  d.bearing = -d.bearing;
  EXPECT_FALSE(TriangulateMidpoint({c, d}, &estimate));
  EXPECT_TRUE(TriangulateMidpoint({Observe(cam_i, point), Observe(cam_j, point)}, &estimate));
}

}  // namespace
}  // namespace pipescope
