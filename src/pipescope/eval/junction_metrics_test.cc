#include "pipescope/eval/junction_metrics.h"

#include <gtest/gtest.h>

#include <cmath>

#include "pipescope/util/error.h"

namespace pipescope {
namespace {

// A square loop of pipe, 2 m a side in the X-Z plane, with a junction at each corner. The
// camera runs round it at 1 m/s, 10 poses a second, passing A at t = 0, B at 2, C at 4, D at 6.
std::vector<Junction> SquareScene() {
  return {{"A", NAN, Eigen::Vector3d(0, 0, 0)},
          {"B", NAN, Eigen::Vector3d(2, 0, 0)},
          {"C", NAN, Eigen::Vector3d(2, 0, 2)},
          {"D", NAN, Eigen::Vector3d(0, 0, 2)}};
}

Trajectory SquareRun() {
  Trajectory trajectory;
  for (int i = 0; i <= 80; ++i) {
    const double s = 0.1 * i;  // Path length, m.
    StampedPose pose;
    pose.timestamp = s;
    if (s <= 2) {
      pose.position = Eigen::Vector3d(s, 0, 0);
    } else if (s <= 4) {
      pose.position = Eigen::Vector3d(2, 0, s - 2);
    } else if (s <= 6) {
      pose.position = Eigen::Vector3d(6 - s, 0, 2);
    } else {
      pose.position = Eigen::Vector3d(0, 0, 8 - s);
    }
    trajectory.push_back(pose);
  }
  return trajectory;
}

TEST(JunctionMetrics, InterpolatesAndClampsGroundTruth) {
  const Trajectory run = SquareRun();
  EXPECT_LT((InterpolatePosition(run, 1.05) - Eigen::Vector3d(1.05, 0, 0)).norm(), 1e-12);
  EXPECT_LT((InterpolatePosition(run, 3.0) - Eigen::Vector3d(2, 0, 1)).norm(), 1e-12);
  EXPECT_EQ(InterpolatePosition(run, -5.0), run.front().position);
  EXPECT_EQ(InterpolatePosition(run, 99.0), run.back().position);
}

TEST(JunctionMetrics, SquareWithStretchedEstimate) {
  // The estimate stretches X by 5 %: A-B and C-D come out 2.1 m, A-D and B-C stay 2 m, the
  // diagonals sqrt(2.1^2 + 2^2). Estimated junctions are listed C, A, D, B with their own names
  // and timestamps a little off the true passing times.
  const std::vector<Junction> estimated = {{"j0", 4.03, Eigen::Vector3d(2.1, 0, 2)},
                                           {"j1", -0.02, Eigen::Vector3d(0, 0, 0)},
                                           {"j2", 6.2, Eigen::Vector3d(0, 0, 2)},
                                           {"j3", 1.9, Eigen::Vector3d(2.1, 0, 0)}};
  const auto distances = EvaluateJunctionDistances(SquareRun(), SquareScene(), estimated);
  ASSERT_EQ(distances.size(), 6u);
  const double diagonal_gt = 2 * std::sqrt(2.0);
  const double diagonal_est = std::sqrt(2.1 * 2.1 + 4.0);
  struct Expected {
    const char* from;
    const char* to;
    double gt_m;
    double est_m;
  };
  const Expected expected[] = {{"C", "A", diagonal_gt, diagonal_est},
                               {"C", "D", 2.0, 2.1},
                               {"C", "B", 2.0, 2.0},
                               {"A", "D", 2.0, 2.0},
                               {"A", "B", 2.0, 2.1},
                               {"D", "B", diagonal_gt, diagonal_est}};
  for (std::size_t k = 0; k < distances.size(); ++k) {
    SCOPED_TRACE(k);
    EXPECT_EQ(distances[k].from, expected[k].from);
    EXPECT_EQ(distances[k].to, expected[k].to);
    EXPECT_NEAR(distances[k].gt_m, expected[k].gt_m, 1e-12);
    EXPECT_NEAR(distances[k].est_m, expected[k].est_m, 1e-12);
    EXPECT_NEAR(distances[k].error_m, expected[k].est_m - expected[k].gt_m, 1e-12);
    EXPECT_NEAR(distances[k].error_pct,
                100 * std::abs(expected[k].est_m - expected[k].gt_m) / expected[k].gt_m, 1e-9);
  }
  EXPECT_NEAR(distances[1].error_pct, 5.0, 1e-9);
  EXPECT_NEAR(distances[0].error_m, diagonal_est - diagonal_gt, 1e-12);
  EXPECT_GT(distances[0].error_m, 0);
}

TEST(JunctionMetrics, DuplicateMatchKeepsTheCloserEstimate) {
  // Both j0 (t = 0.6, 0.6 m from A) and j1 (t = 0.1, 0.1 m from A) map to A; j1 is kept.
  const std::vector<Junction> estimated = {{"j0", 0.6, Eigen::Vector3d(9, 9, 9)},
                                           {"j1", 0.1, Eigen::Vector3d(0, 0, 0.1)},
                                           {"j2", 2.0, Eigen::Vector3d(2, 0, 0.1)}};
  const auto distances = EvaluateJunctionDistances(SquareRun(), SquareScene(), estimated);
  ASSERT_EQ(distances.size(), 1u);
  EXPECT_EQ(distances[0].from, "A");
  EXPECT_EQ(distances[0].to, "B");
  EXPECT_NEAR(distances[0].est_m, 2.0, 1e-12);
  EXPECT_NEAR(distances[0].error_m, 0.0, 1e-12);
}

TEST(JunctionMetrics, EdgeCases) {
  EXPECT_TRUE(EvaluateJunctionDistances(SquareRun(), SquareScene(), {}).empty());
  const std::vector<Junction> one = {{"j0", 2.0, Eigen::Vector3d(2, 0, 0)}};
  EXPECT_TRUE(EvaluateJunctionDistances(SquareRun(), SquareScene(), one).empty());
  EXPECT_THROW(EvaluateJunctionDistances(SquareRun(), {}, one), InputError);
  EXPECT_THROW(EvaluateJunctionDistances({}, SquareScene(), one), InputError);
  const std::vector<Junction> no_time = {{"j0", NAN, Eigen::Vector3d(2, 0, 0)}};
  EXPECT_THROW(EvaluateJunctionDistances(SquareRun(), SquareScene(), no_time), InputError);
}

}  // namespace
}  // namespace pipescope
