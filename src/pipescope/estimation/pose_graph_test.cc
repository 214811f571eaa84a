#include "pipescope/estimation/pose_graph.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "pipescope/util/error.h"

namespace pipescope {
namespace {

using Matrix6d = Eigen::Matrix<double, 6, 6>;

constexpr double kStepM = 0.1;
constexpr int kStepsPerSide = 25;  // a 2.5 m square, 100 steps round
constexpr int kStepsRound = 4 * kStepsPerSide;
constexpr int kStepsPastStart = 12;  // the first side driven again, as a loop closure needs

// A camera looking along its travel (z forward, y down) in the world's X-Y plane, Z up.
Eigen::Isometry3d LookingAlong(const Eigen::Vector3d& position, const Eigen::Vector3d& heading) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  const Eigen::Vector3d z = heading.normalized();
  const Eigen::Vector3d y = -Eigen::Vector3d::UnitZ();
  pose.linear().col(0) = y.cross(z);
  pose.linear().col(1) = y;
  pose.linear().col(2) = z;
  pose.translation() = position;
  return pose;
}

// Round a square, turning left at its corners, and on along the first side: pose k and pose
// kStepsRound + k are at the same place with the same heading.
std::vector<Eigen::Isometry3d> SquareLoop() {
  const Eigen::Vector3d headings[4] = {Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(),
                                       -Eigen::Vector3d::UnitX(), -Eigen::Vector3d::UnitY()};
  std::vector<Eigen::Isometry3d> poses;
  Eigen::Vector3d position(0.4, -0.2, 0.1);
  for (int k = 0; k <= kStepsRound + kStepsPastStart; ++k) {
    const Eigen::Vector3d& heading = headings[(k / kStepsPerSide) % 4];
    poses.push_back(LookingAlong(position, heading));
    position += kStepM * heading;
  }
  return poses;
}

// Odometry that over-reads each step by `scale_error` and turns `yaw_bias_rad` too far left
// (about the camera's up, -y), chained from the true first pose.
std::vector<Eigen::Isometry3d> DriftedOdometry(const std::vector<Eigen::Isometry3d>& truth,
                                               double scale_error, double yaw_bias_rad,
                                               std::vector<PoseGraphEdge>* edges) {
  *edges = ConsecutivePoseEdges(truth, 0.01, 0.005);
  std::vector<Eigen::Isometry3d> chained = {truth.front()};
  for (PoseGraphEdge& edge : *edges) {
    edge.from_T_to.translation() *= 1.0 + scale_error;
    edge.from_T_to.linear() =
        edge.from_T_to.linear() *
        Eigen::AngleAxisd(yaw_bias_rad, -Eigen::Vector3d::UnitY()).toRotationMatrix();
    chained.push_back(chained.back() * edge.from_T_to);
  }
  return chained;
}

// Loop closures between the two passes of the first side, measured exactly.
std::vector<PoseGraphEdge> LoopClosures(const std::vector<Eigen::Isometry3d>& truth) {
  std::vector<PoseGraphEdge> closures;
  for (int k : {2, 6, 10}) {
    const int later = kStepsRound + k;
    closures.push_back(
        {k, later, truth[k].inverse() * truth[later], IsotropicPoseInformation(0.002, 0.002)});
  }
  return closures;
}

// Absolute trajectory error, both trajectories sharing their first pose (the graph's gauge), so
// without an alignment.
double PositionRms(const std::vector<Eigen::Isometry3d>& estimate,
                   const std::vector<Eigen::Isometry3d>& truth) {
  double sum = 0.0;
  for (size_t i = 0; i < truth.size(); ++i) {
    sum += (estimate[i].translation() - truth[i].translation()).squaredNorm();
  }
  return std::sqrt(sum / truth.size());
}

double WorstLoopGap(const std::vector<Eigen::Isometry3d>& poses) {
  double worst = 0.0;
  for (int k = 0; k <= kStepsPastStart; ++k) {
    worst = std::max(worst, (poses[kStepsRound + k].translation() - poses[k].translation()).norm());
  }
  return worst;
}

TEST(OptimisePoseGraph, LoopClosuresUndoOdometryDrift) {
  const std::vector<Eigen::Isometry3d> truth = SquareLoop();
  std::vector<PoseGraphEdge> edges;
  std::vector<Eigen::Isometry3d> poses = DriftedOdometry(truth, 0.01, 0.002, &edges);
  for (const PoseGraphEdge& closure : LoopClosures(truth)) edges.push_back(closure);
  const double gap_before = WorstLoopGap(poses);
  const double ate_before = PositionRms(poses, truth);
  ASSERT_GT(gap_before, 0.1);  // the drift pulls the passes tens of centimetres apart

  const PoseGraphResult result = OptimisePoseGraph(edges, &poses);
  const double gap_after = WorstLoopGap(poses);
  const double ate_after = PositionRms(poses, truth);
  std::printf("loop gap %.4f -> %.4f m, ATE %.4f -> %.4f m, cost %.4g -> %.4g, %d iterations\n",
              gap_before, gap_after, ate_before, ate_after, result.initial_cost, result.final_cost,
              result.iterations);
  EXPECT_TRUE(result.converged);
  EXPECT_LT(result.final_cost, 0.01 * result.initial_cost);
  EXPECT_LT(gap_after, 0.005);
  EXPECT_LT(ate_after, ate_before / 5.0);
  EXPECT_EQ(poses[0].matrix(), truth[0].matrix());
}

// The square loop's four corners as a network's Ts: the odometry exact but for one corner turned
// `wrong_turn_rad` too far left; each corner's steps (two either side) turn freely and the
// corner's turn is one edge of `corner_sigma_rad`, Huber's loss beyond `huber_sigmas` (0:
// squared); the first side's loop closures exact. Returns each corner's turn error after the
// graph, in radians.
std::vector<double> CornerErrorsAfterClosure(double wrong_turn_rad, double corner_sigma_rad,
                                             double huber_sigmas) {
  const std::vector<Eigen::Isometry3d> truth = SquareLoop();
  const int corners[4] = {kStepsPerSide, 2 * kStepsPerSide, 3 * kStepsPerSide, kStepsRound};
  const int wrong = 1;
  std::vector<PoseGraphEdge> edges = ConsecutivePoseEdges(truth, 0.001, 0.05 * M_PI / 180.0);
  const Matrix6d free_turn = IsotropicPoseInformation(0.001, 5.0 * M_PI / 180.0);
  for (int c = 0; c < 4; ++c) {
    for (int k = corners[c] - 2; k < corners[c] + 2; ++k) edges[k].information = free_turn;
  }
  edges[corners[wrong] - 1].from_T_to.linear() =
      edges[corners[wrong] - 1].from_T_to.linear() *
      Eigen::AngleAxisd(wrong_turn_rad, -Eigen::Vector3d::UnitY()).toRotationMatrix();
  std::vector<Eigen::Isometry3d> poses = {truth.front()};
  for (const PoseGraphEdge& edge : edges) poses.push_back(poses.back() * edge.from_T_to);
  for (int c = 0; c < 4; ++c) {
    PoseGraphEdge turn{corners[c] - 2, corners[c] + 2,
                       poses[corners[c] - 2].inverse() * poses[corners[c] + 2],
                       IsotropicPoseInformation(1.0, corner_sigma_rad)};
    turn.huber_scale = huber_sigmas;
    edges.push_back(turn);
  }
  for (const PoseGraphEdge& closure : LoopClosures(truth)) edges.push_back(closure);
  EXPECT_TRUE(OptimisePoseGraph(edges, &poses).converged);
  std::vector<double> errors;
  for (int c = 0; c < 4; ++c) {
    const auto turn = [&](const std::vector<Eigen::Isometry3d>& p) {
      return p[corners[c] - 2].linear().transpose() * p[corners[c] + 2].linear();
    };
    errors.push_back(Eigen::AngleAxisd(turn(truth).transpose() * turn(poses)).angle());
  }
  return errors;
}

// A loop's closure fixes where it ends, not which corner was wrong: with squared errors one
// corner's 9 degrees are spread over every corner (and a little over the sides), so the right
// corners end degrees off. With Huber's loss on the corners' turns the closure puts nearly all
// of it where it belongs (route B's T2, docs/fisheye_mapping.md).
TEST(OptimisePoseGraph, HuberLossPutsOneWrongCornersErrorOnThatCorner) {
  const double deg = M_PI / 180.0;
  const std::vector<double> squared = CornerErrorsAfterClosure(9.0 * deg, 0.5 * deg, 0.0);
  const std::vector<double> huber = CornerErrorsAfterClosure(9.0 * deg, 0.5 * deg, 1.0);
  double worst_squared = 0.0, worst_huber = 0.0, right_squared = 0.0, right_huber = 0.0;
  for (int c = 0; c < 4; ++c) {
    std::printf("corner %d: %.3f deg off with squared errors, %.3f deg with Huber's loss\n", c,
                squared[c] / deg, huber[c] / deg);
    worst_squared = std::max(worst_squared, squared[c]);
    worst_huber = std::max(worst_huber, huber[c]);
    if (c != 1) right_squared += squared[c], right_huber += huber[c];
  }
  EXPECT_GT(worst_squared, 3.0 * deg);  // the wrong corner keeps more than a third
  EXPECT_GT(right_squared, 3.0 * deg);  // and the right ones take degrees
  EXPECT_LT(worst_huber, 0.75 * deg);
  EXPECT_LT(worst_huber, 0.2 * worst_squared);
  EXPECT_LT(right_huber, 0.25 * right_squared);
}

TEST(OptimisePoseGraph, ConsistentGraphStaysPut) {
  const std::vector<Eigen::Isometry3d> truth = SquareLoop();
  std::vector<PoseGraphEdge> edges = ConsecutivePoseEdges(truth, 0.01, 0.005);
  for (const PoseGraphEdge& closure : LoopClosures(truth)) edges.push_back(closure);
  std::vector<Eigen::Isometry3d> poses = truth;
  const PoseGraphResult result = OptimisePoseGraph(edges, &poses);
  EXPECT_LT(result.initial_cost, 1e-18);
  EXPECT_LT(result.final_cost, 1e-18);
  for (size_t i = 0; i < truth.size(); ++i) {
    EXPECT_LT((poses[i].translation() - truth[i].translation()).norm(), 1e-9) << i;
    EXPECT_LT((poses[i].linear() - truth[i].linear()).norm(), 1e-9) << i;
  }
}

// One edge whose error is known in closed form: the translation error lies in the `from` frame,
// the rotation error is 2 sin(angle / 2) about the axis, and the information weights them in the
// order [translation, rotation].
TEST(OptimisePoseGraph, ErrorOfOneEdgeMatchesItsClosedForm) {
  Eigen::Isometry3d from = Eigen::Isometry3d::Identity();
  from.linear() = Eigen::AngleAxisd(M_PI / 2.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  from.translation() = Eigen::Vector3d(1.0, 2.0, 3.0);
  const Eigen::Isometry3d to = from * Eigen::Translation3d(0.0, 0.05, 0.0);
  PoseGraphEdge edge;
  edge.from = 0;
  edge.to = 1;
  const double angle = 0.2;
  edge.from_T_to = Eigen::Translation3d(0.1, 0.0, 0.0) *
                   Eigen::AngleAxisd(angle, Eigen::Vector3d(0.0, 0.6, 0.8));
  const double translation_sigma = 0.01, rotation_sigma = 0.02;
  edge.information = IsotropicPoseInformation(translation_sigma, rotation_sigma);
  std::vector<Eigen::Isometry3d> poses = {from, to};

  const PoseGraphResult result = OptimisePoseGraph({edge}, &poses);
  const double translation_error_squared = 0.1 * 0.1 + 0.05 * 0.05;  // (-0.1, 0.05, 0) in `from`
  const double rotation_error = 2.0 * std::sin(angle / 2.0);
  const double expected = 0.5 * (translation_error_squared / std::pow(translation_sigma, 2) +
                                 std::pow(rotation_error / rotation_sigma, 2));
  EXPECT_NEAR(result.initial_cost, expected, 1e-9 * expected);
  EXPECT_LT(result.final_cost, 1e-10 * result.initial_cost);
  const Eigen::Isometry3d expected_to = from * edge.from_T_to;
  EXPECT_LT((poses[1].translation() - expected_to.translation()).norm(), 1e-6);
  EXPECT_LT((poses[1].linear() - expected_to.linear()).norm(), 1e-6);
}

// The graph fixes only relative poses; the first pose holds the gauge. Moving it moves the whole
// solution rigidly with it.
TEST(OptimisePoseGraph, FirstPoseStaysFixed) {
  const std::vector<Eigen::Isometry3d> truth = SquareLoop();
  std::vector<PoseGraphEdge> edges = ConsecutivePoseEdges(truth, 0.01, 0.005);
  for (const PoseGraphEdge& closure : LoopClosures(truth)) edges.push_back(closure);
  std::vector<Eigen::Isometry3d> poses = truth;
  const Eigen::Isometry3d moved_first =
      truth[0] * Eigen::Translation3d(0.3, -0.1, 0.2) *
      Eigen::AngleAxisd(0.4, Eigen::Vector3d(1.0, 2.0, 3.0).normalized());
  poses[0] = moved_first;

  const PoseGraphResult result = OptimisePoseGraph(edges, &poses);
  EXPECT_GT(result.initial_cost, 1.0);
  EXPECT_LT(result.final_cost, 1e-12);
  EXPECT_EQ(poses[0].matrix(), moved_first.matrix());  // bit for bit
  const Eigen::Isometry3d rigid = moved_first * truth[0].inverse();
  for (size_t i = 1; i < truth.size(); ++i) {
    const Eigen::Isometry3d expected = rigid * truth[i];
    EXPECT_LT((poses[i].translation() - expected.translation()).norm(), 1e-6) << i;
    EXPECT_LT((poses[i].linear() - expected.linear()).norm(), 1e-6) << i;
  }
}

// Runs OptimisePoseGraph on three poses with `bad` as edge 1 and returns the InputError's
// message, or "" when none was thrown.
std::string ErrorOfBadEdge(const PoseGraphEdge& bad) {
  std::vector<Eigen::Isometry3d> poses(3, Eigen::Isometry3d::Identity());
  std::vector<PoseGraphEdge> edges = {{0, 1, Eigen::Isometry3d::Identity(), Matrix6d::Identity()},
                                      bad};
  try {
    OptimisePoseGraph(edges, &poses);
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

TEST(OptimisePoseGraph, InvalidEdgesAreRejectedByName) {
  const PoseGraphEdge good = {1, 2, Eigen::Isometry3d::Identity(), Matrix6d::Identity()};
  EXPECT_EQ(ErrorOfBadEdge(good), "");

  PoseGraphEdge out_of_range = good;
  out_of_range.to = 3;
  EXPECT_NE(ErrorOfBadEdge(out_of_range).find("edge 1 (1 -> 3)"), std::string::npos);
  PoseGraphEdge negative = good;
  negative.from = -1;
  EXPECT_NE(ErrorOfBadEdge(negative).find("edge 1 (-1 -> 2)"), std::string::npos);
  PoseGraphEdge to_itself = good;
  to_itself.to = 1;
  EXPECT_NE(ErrorOfBadEdge(to_itself).find("edge 1"), std::string::npos);

  PoseGraphEdge zero_information = good;
  zero_information.information.setZero();
  EXPECT_NE(ErrorOfBadEdge(zero_information).find("edge 1"), std::string::npos);
  PoseGraphEdge indefinite = good;
  indefinite.information(4, 4) = -1.0;
  EXPECT_NE(ErrorOfBadEdge(indefinite).find("edge 1"), std::string::npos);
  PoseGraphEdge asymmetric = good;
  asymmetric.information(0, 5) = 0.5;
  EXPECT_NE(ErrorOfBadEdge(asymmetric).find("edge 1"), std::string::npos);
  PoseGraphEdge negative_huber = good;
  negative_huber.huber_scale = -1.0;
  EXPECT_NE(ErrorOfBadEdge(negative_huber).find("edge 1"), std::string::npos);
  PoseGraphEdge not_finite = good;
  not_finite.from_T_to.translation().x() = NAN;
  EXPECT_NE(ErrorOfBadEdge(not_finite).find("edge 1"), std::string::npos);
}

}  // namespace
}  // namespace pipescope
