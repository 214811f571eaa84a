#include "pipescope/synthetic/trajectory_generator.h"

#include <gtest/gtest.h>

#include <cmath>

namespace pipescope {
namespace {

CentrelinePath StraightPipe(double length) {
  return CentrelinePath({{0, 0, 0}, {0, 0, length}}, 1.0);
}

TEST(TrajectoryGenerator, OneWayRunCoversSpeedTimesDuration) {
  MotionOptions options;
  options.fps = 10.0;
  options.frames = 301;
  options.speed_m_s = 0.02;
  options.speed_variation = 0.0;
  options.travel_m = 10.0;
  const TrajectoryGenerator generator(StraightPipe(20.0), options, Eigen::Isometry3d::Identity());
  const Trajectory frames = generator.Frames();
  ASSERT_EQ(frames.size(), 301u);
  EXPECT_NEAR(frames.back().timestamp, 30.0, 1e-12);
  // No noise: the camera rides the axis, 0.02 m/s for 30 s.
  EXPECT_NEAR(frames.back().position.z() - frames.front().position.z(), 0.6, 1e-9);
  EXPECT_NEAR(frames.back().position.head<2>().norm(), 0.0, 1e-12);
}

TEST(TrajectoryGenerator, StopsAreExactlyStillAndOutAndBackReturns) {
  MotionOptions options;
  options.fps = 10.0;
  options.frames = 600;
  options.speed_m_s = 0.05;
  options.speed_variation = 0.2;
  options.stop_count = 2;
  options.stop_duration_s = 3.0;
  options.start_s_m = 0.5;
  options.travel_m = 1.0;
  options.out_and_back = true;
  options.lateral_offset_m = 0.003;
  options.roll_deg = 2.0;
  options.wobble_deg = 1.0;
  const TrajectoryGenerator generator(StraightPipe(2.0), options, Eigen::Isometry3d::Identity());
  const Trajectory frames = generator.Frames();
  int still_pairs = 0;
  double farthest = 0.0;
  for (std::size_t i = 1; i < frames.size(); ++i) {
    const bool same_place = frames[i].position == frames[i - 1].position;
    const bool same_attitude = frames[i].rotation.coeffs() == frames[i - 1].rotation.coeffs();
    EXPECT_EQ(same_place, same_attitude) << "frame " << i;
    still_pairs += same_place;
    farthest = std::max(farthest, generator.ArcLength(frames[i].timestamp) - 0.5);
  }
  // Two 3 s stops at 10 fps, less the ramps, and the wait at the end once back at the start.
  EXPECT_GE(still_pairs, 2 * 20);
  // The turnaround falls between frames: within one frame's travel of the set distance.
  EXPECT_LE(farthest, 1.0 + 1e-9);
  EXPECT_GT(farthest, 1.0 - 0.05 * 1.2 / 10.0);
  EXPECT_NEAR(generator.ArcLength(frames.back().timestamp), 0.5, 1e-9);
}

TEST(TrajectoryGenerator, WallMountLooksDownWithImageXAlongTheAxis) {
  MotionOptions options;
  options.frames = 2;
  options.travel_m = 1.0;
  Eigen::Isometry3d body_from_cam = Eigen::Isometry3d::Identity();
  body_from_cam.linear().col(0) = Eigen::Vector3d::UnitZ();
  body_from_cam.linear().col(1) = Eigen::Vector3d::UnitX();
  body_from_cam.linear().col(2) = Eigen::Vector3d::UnitY();
  const TrajectoryGenerator generator(StraightPipe(2.0), options, body_from_cam);
  const Eigen::Isometry3d pose = generator.NominalWorldFromCam(0.3);
  // 000 eq. 18: principal axis along the pipe's Y, image x along the pipe axis (Z).
  EXPECT_TRUE(pose.linear().col(2).isApprox(Eigen::Vector3d::UnitY(), 1e-12));
  EXPECT_TRUE(pose.linear().col(0).isApprox(Eigen::Vector3d::UnitZ(), 1e-12));
  EXPECT_NEAR(pose.linear().determinant(), 1.0, 1e-12);
  EXPECT_TRUE(pose.translation().isApprox(Eigen::Vector3d(0, 0, 0.3), 1e-12));
}

// wander_wavelength_m slows the offset from the axis (a crawler's wander over metres) and leaves
// the roll and wobble as they were.
TEST(TrajectoryGenerator, WanderWavelengthSlowsTheOffsetOnly) {
  MotionOptions options;
  options.fps = 10.0;
  options.frames = 400;
  options.speed_m_s = 0.05;
  options.travel_m = 3.0;
  options.lateral_offset_m = 0.004;
  options.roll_deg = 2.0;
  options.wobble_deg = 1.0;
  options.wobble_wavelength_m = 0.5;
  MotionOptions slow = options;
  slow.wander_wavelength_m = 2.0;
  const Trajectory fast_frames =
      TrajectoryGenerator(StraightPipe(5.0), options, Eigen::Isometry3d::Identity()).Frames();
  const Trajectory slow_frames =
      TrajectoryGenerator(StraightPipe(5.0), slow, Eigen::Isometry3d::Identity()).Frames();
  double fast_change = 0.0, slow_change = 0.0;
  for (std::size_t i = 1; i < fast_frames.size(); ++i) {
    fast_change += (fast_frames[i].position - fast_frames[i - 1].position).head<2>().norm();
    slow_change += (slow_frames[i].position - slow_frames[i - 1].position).head<2>().norm();
    EXPECT_TRUE(fast_frames[i].rotation.isApprox(slow_frames[i].rotation, 1e-12)) << i;
    EXPECT_NEAR(fast_frames[i].position.z(), slow_frames[i].position.z(), 1e-12);
  }
  // Four times the wavelength: about a quarter of the sideways speed.
  EXPECT_LT(slow_change, 0.5 * fast_change);
  EXPECT_GT(slow_change, 0.1 * fast_change);
}

TEST(SmoothNoise, BoundedAndSmooth) {
  const SmoothNoise noise(42, 0.5);
  double previous = noise(0.0);
  for (double u = 0.001; u < 10.0; u += 0.001) {
    const double value = noise(u);
    EXPECT_LE(std::abs(value), 1.0);
    EXPECT_LT(std::abs(value - previous), 0.05);
    previous = value;
  }
}

}  // namespace
}  // namespace pipescope
