#include "pipescope/eval/trajectory_metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "pipescope/util/error.h"

namespace pipescope {
namespace {

// Builds a trajectory sampled at 10 Hz from a position function of the frame index.
Trajectory MakeTrajectory(int frames, const std::function<Eigen::Vector3d(int)>& position,
                          const Eigen::Quaterniond& rotation = Eigen::Quaterniond::Identity()) {
  Trajectory trajectory;
  for (int i = 0; i < frames; ++i) {
    StampedPose pose;
    pose.timestamp = 100.0 + 0.1 * i;
    pose.position = position(i);
    pose.rotation = rotation;
    trajectory.push_back(pose);
  }
  return trajectory;
}

// Straight down the pipe axis (Z), `step_m` a frame.
Trajectory Straight(int frames, double step_m) {
  return MakeTrajectory(frames, [=](int i) { return Eigen::Vector3d(0, 0, step_m * i); });
}

// Applies `scale * rotation * p + translation` to the positions and `rotation` to the poses:
// the same trajectory in another (similarity) frame.
Trajectory Transformed(const Trajectory& trajectory, const Eigen::Quaterniond& rotation,
                       const Eigen::Vector3d& translation, double scale) {
  Trajectory out = trajectory;
  for (StampedPose& pose : out) {
    pose.position = scale * (rotation * pose.position) + translation;
    pose.rotation = rotation * pose.rotation;
  }
  return out;
}

// A curved 3D path with turning camera, so alignment is well determined.
Trajectory Helix(int frames) {
  Trajectory trajectory = MakeTrajectory(frames, [](int i) {
    const double angle = 0.05 * i;
    return Eigen::Vector3d(std::cos(angle), std::sin(angle), 0.03 * i);
  });
  for (std::size_t i = 0; i < trajectory.size(); ++i) {
    trajectory[i].rotation = Eigen::AngleAxisd(0.05 * i, Eigen::Vector3d::UnitZ());
  }
  return trajectory;
}

const Eigen::Quaterniond kRotation(Eigen::AngleAxisd(0.4,
                                                     Eigen::Vector3d(1.0, 2.0, -0.5).normalized()));
const Eigen::Vector3d kTranslation(0.3, -1.2, 5.0);

// A network's L: 2 m along x, a 90 deg turn, 2 m along y, 1 cm a frame. The estimate is 1 %
// long and turns 10 deg too far: its chord from start to end is off by the turn (closed form),
// its path by the 1 % alone. Jitter across the path (0.5 mm, aperiodic) lengthens the path by
// 0.2 % frame by frame, by under 0.08 % over the default 2 cm steps.
TEST(TrajectoryMetrics, ThePathLengthDoesNotDependOnTheTurnsAngle) {
  const double turn = 10.0 * M_PI / 180.0;
  const auto l_shape = [](double scale, double extra_turn, double jitter_m) {
    return MakeTrajectory(401, [=](int i) {
      const double side = jitter_m * std::sin(2.1 * i);
      if (i <= 200) return Eigen::Vector3d(scale * 0.01 * i, side, 0.0);
      const double along = scale * 0.01 * (i - 200);
      return Eigen::Vector3d(scale * 2.0 - along * std::sin(extra_turn) + side,
                             along * std::cos(extra_turn), 0.0);
    });
  };
  const Trajectory gt = l_shape(1.0, 0.0, 0.0);
  const Metrics metrics = EvaluateTrajectory(gt, l_shape(1.01, turn, 0.0), {});
  // The 2 cm steps cut the sharp corner by up to 6 mm (a pipe's turn has a radius).
  EXPECT_NEAR(metrics.path_gt_m, 4.0, 0.006);
  ASSERT_TRUE(metrics.path_error_pct);
  EXPECT_NEAR(*metrics.path_error_pct, 1.0, 0.05);
  // The chord: sides of 2.02 m meeting at 80 deg against 2 m at 90 deg.
  const double chord_est = 2.02 * std::sqrt(2.0 - 2.0 * std::cos(M_PI / 2 - turn));
  ASSERT_TRUE(metrics.distance_error_pct);
  EXPECT_NEAR(*metrics.distance_error_pct, 100.0 * (1.0 - chord_est / std::sqrt(8.0)), 1e-9);
  EXPECT_GT(*metrics.distance_error_pct, 7.0);

  const Trajectory jittered = l_shape(1.0, 0.0, 5e-4);
  EvaluationOptions every_frame;
  every_frame.path_step_m = 0.0;
  EXPECT_GT(*EvaluateTrajectory(gt, jittered, every_frame).path_error_pct, 0.15);
  EXPECT_LT(*EvaluateTrajectory(gt, jittered, {}).path_error_pct, 0.08);
}

TEST(TrajectoryMetrics, OneWayScaledEstimateHasOnePercentDistanceError) {
  const Trajectory gt = Straight(51, 0.1);  // 5 m.
  const Trajectory est =
      Transformed(gt, Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero(), 1.01);
  const Metrics metrics = EvaluateTrajectory(gt, est, {});
  EXPECT_EQ(metrics.frames_gt, 51u);
  EXPECT_EQ(metrics.frames_est, 51u);
  EXPECT_EQ(metrics.frames_matched, 51u);
  EXPECT_FALSE(metrics.out_and_back);
  EXPECT_NEAR(metrics.distance_gt_m, 5.0, 1e-12);
  EXPECT_NEAR(metrics.distance_est_m, 5.05, 1e-12);
  ASSERT_TRUE(metrics.distance_error_pct);
  EXPECT_NEAR(*metrics.distance_error_pct, 1.0, 1e-9);
  EXPECT_FALSE(metrics.forward_error_pct);
  EXPECT_FALSE(metrics.reverse_error_pct);
  EXPECT_FALSE(metrics.return_error_pct);
  // SE(3) on a collinear run can only shift: residuals 0.01 (z - mean z), so the RMSE is 0.01
  // times the standard deviation of the grid 0, 0.1, ..., 5 and the maximum is 0.01 * 2.5.
  EXPECT_EQ(metrics.alignment, Alignment::kSe3);
  EXPECT_FALSE(metrics.scale);
  EXPECT_NEAR(metrics.ate_rmse_m, 0.01 * 0.1 * std::sqrt((51.0 * 51.0 - 1.0) / 12.0), 1e-12);
  EXPECT_NEAR(metrics.ate_max_m, 0.025, 1e-12);
}

TEST(TrajectoryMetrics, OutAndBackLegErrors) {
  // Ground truth 2 m out along Z and 2 m back; the estimate goes 2.02 m out and 1.98 m back.
  const auto out_and_back = [](double forward_step, double reverse_step) {
    return [=](int i) {
      return Eigen::Vector3d(
          0, 0, i <= 20 ? forward_step * i : forward_step * 20 - reverse_step * (i - 20));
    };
  };
  const Trajectory gt = MakeTrajectory(41, out_and_back(0.1, 0.1));
  const Trajectory est = MakeTrajectory(41, out_and_back(0.101, 0.099));
  const Metrics metrics = EvaluateTrajectory(gt, est, {});
  EXPECT_TRUE(metrics.out_and_back);
  EXPECT_NEAR(metrics.distance_gt_m, 4.0, 1e-12);
  EXPECT_NEAR(metrics.distance_est_m, 4.0, 1e-12);
  ASSERT_TRUE(metrics.distance_error_pct && metrics.forward_error_pct &&
              metrics.reverse_error_pct && metrics.return_error_pct);
  EXPECT_NEAR(*metrics.distance_error_pct, 0.0, 1e-9);
  EXPECT_NEAR(*metrics.forward_error_pct, 1.0, 1e-9);
  EXPECT_NEAR(*metrics.reverse_error_pct, 1.0, 1e-9);
  // 000 eq. 51: 100 |2.02 - 1.98| / (2 * 2).
  EXPECT_NEAR(*metrics.return_error_pct, 1.0, 1e-9);
}

TEST(TrajectoryMetrics, OutAndBackThresholdFollowsTheReturnedFraction) {
  // Out 2 m, back 1.7 m (85 %, ending 0.3 m from the start): out and back by default (half).
  const Trajectory gt = MakeTrajectory(
      38, [](int i) { return Eigen::Vector3d(0, 0, i <= 20 ? 0.1 * i : 2.0 - 0.1 * (i - 20)); });
  EvaluationOptions options;
  Metrics metrics = EvaluateTrajectory(gt, gt, options);
  EXPECT_TRUE(metrics.out_and_back);
  EXPECT_NEAR(metrics.distance_gt_m, 3.7, 1e-12);
  EXPECT_NEAR(*metrics.return_error_pct, 0.0, 1e-12);
  options.min_return_fraction = 0.9;
  metrics = EvaluateTrajectory(gt, gt, options);
  EXPECT_FALSE(metrics.out_and_back);
  EXPECT_NEAR(metrics.distance_gt_m, 0.3, 1e-12);  // one-way: the net displacement
  // Out 2 m, back 0.4 m (20 %): one-way by default.
  const Trajectory short_return = MakeTrajectory(
      25, [](int i) { return Eigen::Vector3d(0, 0, i <= 20 ? 0.1 * i : 2.0 - 0.1 * (i - 20)); });
  EXPECT_FALSE(EvaluateTrajectory(short_return, short_return, {}).out_and_back);
}

TEST(TrajectoryMetrics, ARunThatComesBackMostOfTheWayIsScoredByItsLegs) {
  // The culvert's seed 43: 1 m out, 0.81 m back. The estimate is 0.1 % long out and 2 mm short
  // of that back: by its legs 0.01 % over the 1.81 m; by its net displacement (0.192 m for
  // 0.190 m), the one-way score before, 1.2 %.
  const auto path = [](double out, double back) {
    return [out, back](int i) {
      return Eigen::Vector3d(0, 0, i <= 100 ? out * i / 100 : out - back * (i - 100) / 81.0);
    };
  };
  const Trajectory gt = MakeTrajectory(182, path(1.0, 0.81));
  const Trajectory est = MakeTrajectory(182, path(1.001, 0.81 * 1.001 - 0.002));
  const Metrics metrics = EvaluateTrajectory(gt, est, {});
  ASSERT_TRUE(metrics.out_and_back);
  EXPECT_NEAR(metrics.distance_gt_m, 1.81, 1e-12);
  EXPECT_NEAR(*metrics.forward_error_pct, 0.1, 1e-9);
  EXPECT_LT(*metrics.distance_error_pct, 0.2);
}

TEST(TrajectoryMetrics, ReturnErrorComparesTheLegsNotWhereTheRunsEnd) {
  // The truth goes 2 m out and 2 m back down the pipe while drifting 4 mm sideways (X); the
  // estimate goes 2.01 m out and 2 m back straight down the axis. Eq. 51: 100 |2.01 - 2| / 4
  // = 0.25 %, up to the drift's second-order change of the truth's leg lengths (2e-6 m).
  const auto drifting = [](int i) {
    return Eigen::Vector3d(1e-4 * i, 0, i <= 20 ? 0.1 * i : 2.0 - 0.1 * (i - 20));
  };
  const Trajectory gt = MakeTrajectory(41, drifting);
  const Trajectory est = MakeTrajectory(41, [](int i) {
    return Eigen::Vector3d(0, 0, i <= 20 ? 0.1005 * i : 2.01 - 0.1 * (i - 20));
  });
  const Metrics metrics = EvaluateTrajectory(gt, est, {});
  ASSERT_TRUE(metrics.out_and_back && metrics.return_error_pct);
  EXPECT_NEAR(*metrics.return_error_pct, 0.25, 1e-4);
  // An estimate that comes back exactly to its start scores the truth's leg difference only,
  // not its 4 mm end offset (0.1 % of the path).
  const Trajectory back_home = MakeTrajectory(
      41, [](int i) { return Eigen::Vector3d(0, 0, i <= 20 ? 0.1 * i : 2.0 - 0.1 * (i - 20)); });
  const Metrics home = EvaluateTrajectory(gt, back_home, {});
  ASSERT_TRUE(home.return_error_pct);
  EXPECT_LT(*home.return_error_pct, 1e-4);
}

TEST(TrajectoryMetrics, RigidCopyHasZeroErrorsUnderSe3) {
  const Trajectory gt = Helix(100);
  const Trajectory est = Transformed(gt, kRotation, kTranslation, 1.0);
  const Metrics metrics = EvaluateTrajectory(gt, est, {});
  EXPECT_LT(metrics.ate_rmse_m, 1e-9);
  EXPECT_LT(metrics.ate_max_m, 1e-9);
  EXPECT_NEAR(*metrics.distance_error_pct, 0.0, 1e-9);
  ASSERT_TRUE(metrics.rpe_1m_pct);
  EXPECT_LT(*metrics.rpe_1m_pct, 1e-9);
  EXPECT_LT(metrics.rot_max_deg, 1e-6);
}

// Right positions, cameras turned: the orientation error is the turn, which ATE cannot see.
TEST(TrajectoryMetrics, OrientationErrorIsTheAngleOfTheCamerasTurn) {
  const Trajectory gt = Helix(60);
  Trajectory est = gt;
  for (std::size_t i = 0; i < est.size(); ++i) {
    // A turn growing to 3 degrees about each camera's own axis (a drifting roll).
    const double angle = 3.0 * M_PI / 180.0 * i / (est.size() - 1);
    est[i].rotation = est[i].rotation * Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ());
  }
  const Metrics metrics =
      EvaluateTrajectory(gt, Transformed(est, kRotation, kTranslation, 1.0), {});
  EXPECT_LT(metrics.ate_max_m, 1e-9);
  EXPECT_NEAR(metrics.rot_max_deg, 3.0, 1e-9);
  double sum = 0.0;
  for (std::size_t i = 0; i < est.size(); ++i) {
    const double angle = 3.0 * i / (est.size() - 1);
    sum += angle * angle;
  }
  EXPECT_NEAR(metrics.rot_rmse_deg, std::sqrt(sum / est.size()), 1e-9);
}

TEST(TrajectoryMetrics, StraightRigidCopyHasZeroAteDespiteDegenerateAlignment) {
  const Trajectory gt = Straight(40, 0.05);
  const Metrics metrics = EvaluateTrajectory(gt, Transformed(gt, kRotation, kTranslation, 1.0), {});
  EXPECT_LT(metrics.ate_max_m, 1e-9);
}

TEST(TrajectoryMetrics, NoAlignmentReportsKnownOffset) {
  const Trajectory gt = Helix(50);
  const Eigen::Vector3d offset(0.03, -0.04, 0.12);  // |offset| = 0.13 m.
  EvaluationOptions options;
  options.alignment = Alignment::kNone;
  const Metrics metrics =
      EvaluateTrajectory(gt, Transformed(gt, Eigen::Quaterniond::Identity(), offset, 1.0), options);
  EXPECT_EQ(metrics.alignment, Alignment::kNone);
  EXPECT_NEAR(metrics.ate_rmse_m, 0.13, 1e-12);
  EXPECT_NEAR(metrics.ate_max_m, 0.13, 1e-12);
  // Aligned, the offset disappears.
  EXPECT_LT(EvaluateTrajectory(gt, Transformed(gt, Eigen::Quaterniond::Identity(), offset, 1.0), {})
                .ate_rmse_m,
            1e-9);
}

TEST(TrajectoryMetrics, Sim3RecoversKnownScale) {
  const Trajectory gt = Helix(80);
  const Trajectory est = Transformed(gt, kRotation, kTranslation, 0.5);  // Half-size estimate.
  EvaluationOptions options;
  options.alignment = Alignment::kSim3;
  const Metrics metrics = EvaluateTrajectory(gt, est, options);
  ASSERT_TRUE(metrics.scale);
  EXPECT_NEAR(*metrics.scale, 2.0, 1e-9);  // Ground truth = 2 x estimate.
  EXPECT_LT(metrics.ate_rmse_m, 1e-9);
  EXPECT_NEAR(*metrics.distance_error_pct, 50.0, 1e-9);
}

TEST(TrajectoryMetrics, RpeOfConstantHeadingErrorHasClosedForm) {
  // The camera looks along the pipe axis with a fixed roll; the estimate keeps the orientation
  // but its translation veers theta off the axis (a yaw about Y). Over every 1 m segment the
  // error is |R_theta d - d| = 2 sin(theta / 2) |d| with |d| = 1 m.
  const double theta = 2.0 * M_PI / 180.0;
  const Eigen::Quaterniond camera(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()));
  const Trajectory gt = MakeTrajectory(
      31, [](int i) { return Eigen::Vector3d(0, 0, 0.1 * i); }, camera);
  const Eigen::Matrix3d veer =
      Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Trajectory est = MakeTrajectory(
      31, [&](int i) { return Eigen::Vector3d(veer * Eigen::Vector3d(0, 0, 0.1 * i)); }, camera);
  const Metrics metrics = EvaluateTrajectory(gt, est, {});
  ASSERT_TRUE(metrics.rpe_1m_pct);
  EXPECT_NEAR(*metrics.rpe_1m_pct, 100.0 * 2.0 * std::sin(theta / 2), 1e-9);
  // The same estimate with its camera turned with its path has no relative error.
  const Trajectory consistent =
      Transformed(gt, Eigen::Quaterniond(veer), Eigen::Vector3d::Zero(), 1.0);
  EXPECT_LT(*EvaluateTrajectory(gt, consistent, {}).rpe_1m_pct, 1e-9);
}

TEST(TrajectoryMetrics, RpeSegmentsAreMeasuredAlongTheGroundTruthPath) {
  // Half-metre segments on a run with a 3 % scale error: every segment is 0.5 m of ground truth
  // and 0.515 m of estimate, an error of 0.015 m = 3 % of the segment.
  const Trajectory gt = Straight(31, 0.1);
  const Trajectory est =
      Transformed(gt, Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero(), 1.03);
  EvaluationOptions options;
  options.rpe_segment_m = 0.5;
  EXPECT_NEAR(*EvaluateTrajectory(gt, est, options).rpe_1m_pct, 3.0, 1e-9);
}

TEST(TrajectoryMetrics, RpeIsNullForRunShorterThanSegment) {
  const Trajectory gt = Straight(11, 0.05);  // 0.5 m.
  const Metrics metrics = EvaluateTrajectory(gt, gt, {});
  EXPECT_FALSE(metrics.rpe_1m_pct);
  EXPECT_NEAR(metrics.distance_gt_m, 0.5, 1e-12);
}

TEST(TrajectoryMetrics, UsesMatchedFramesOnly) {
  const Trajectory gt = Straight(21, 0.1);
  Trajectory est = gt;
  // Extra estimated poses between ground-truth times, far off: they must not count.
  for (int i = 0; i < 5; ++i) {
    StampedPose stray;
    stray.timestamp = 100.05 + 0.1 * i;
    stray.position = Eigen::Vector3d(50, 50, 50);
    est.push_back(stray);
  }
  std::sort(est.begin(), est.end(),
            [](const StampedPose& a, const StampedPose& b) { return a.timestamp < b.timestamp; });
  const Metrics metrics = EvaluateTrajectory(gt, est, {});
  EXPECT_EQ(metrics.frames_gt, 21u);
  EXPECT_EQ(metrics.frames_est, 26u);
  EXPECT_EQ(metrics.frames_matched, 21u);
  EXPECT_LT(metrics.ate_max_m, 1e-12);
  EXPECT_NEAR(*metrics.distance_error_pct, 0.0, 1e-12);
}

TEST(TrajectoryMetrics, TooFewMatchedFramesIsAnInputError) {
  const Trajectory gt = Straight(10, 0.1);
  Trajectory est = gt;
  for (StampedPose& pose : est) pose.timestamp += 1000;
  est[0].timestamp = gt[9].timestamp;  // One match only.
  std::sort(est.begin(), est.end(),
            [](const StampedPose& a, const StampedPose& b) { return a.timestamp < b.timestamp; });
  try {
    EvaluateTrajectory(gt, est, {});
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("only 1"), std::string::npos) << error.what();
  }
}

TEST(TrajectoryMetrics, PercentErrorFollowsEquation50) {
  EXPECT_NEAR(*PercentError(5844.4, 5797.7), 0.799, 5e-4);  // 000 Table 2a, full search.
  EXPECT_NEAR(*PercentError(5844.4, 5853.4), 0.154, 5e-4);
  EXPECT_FALSE(PercentError(0.0, 1.0));
}

}  // namespace
}  // namespace pipescope
