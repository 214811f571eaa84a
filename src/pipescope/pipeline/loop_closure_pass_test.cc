#include "pipescope/pipeline/loop_closure_pass.h"

#include <gtest/gtest.h>

#include <cmath>

namespace pipescope {
namespace {

LoopClosureRecord WithRevisit(bool applied, double gap_before_m, double gap_after_m) {
  LoopClosureRecord record;
  record.applied = applied;
  JunctionRevisit revisit;
  revisit.name = "T4";
  revisit.t_sections = {3, 11};
  revisit.gap_before_m = gap_before_m;
  revisit.gap_after_m = gap_after_m;
  revisit.path_between_m = 24.5;
  record.revisits.push_back(revisit);
  return record;
}

// A junction placed twice, 9.4 m apart after 24.5 m of path, is a map that disagrees with
// itself: the run is unreliable, and the reason names the junction. Within 1 % of the path it is
// not; after a closure, the gap after it counts.
TEST(LoopClosurePass, ARevisitedJunctionPlacedApartMakesTheRunUnreliable) {
  const std::vector<std::string> reasons = RevisitReasons(WithRevisit(false, 9.4, 9.4));
  ASSERT_EQ(reasons.size(), 1u);
  EXPECT_NE(reasons[0].find("T4"), std::string::npos) << reasons[0];
  EXPECT_NE(reasons[0].find("no loop closure"), std::string::npos) << reasons[0];
  EXPECT_TRUE(RevisitReasons(WithRevisit(false, 0.2, 0.2)).empty());
  EXPECT_TRUE(RevisitReasons(WithRevisit(true, 9.4, 0.2)).empty());
  EXPECT_EQ(RevisitReasons(WithRevisit(true, 0.2, 0.3)).size(), 1u);
}

// Straight (key frames 0-4), a T (5-7), straight (8-11): each step one edge, the T's steps free
// to turn, one unconfirmed straight step loose on both, and one edge from P_r (3) to P_b (8)
// measuring the turn between them with Huber's loss.
TEST(LoopClosurePass, GraphEdgesCarryEachTsTurnOnOneRobustEdge) {
  std::vector<Eigen::Isometry3d> poses;
  for (int k = 0; k < 12; ++k) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = Eigen::AngleAxisd(k < 6 ? 0.0 : (k < 8 ? 0.5 : 1.5) * M_PI / 4.0,
                                      Eigen::Vector3d::UnitY())
                        .toRotationMatrix();
    pose.translation() = Eigen::Vector3d(0.01 * k * k, 0.0, 0.1 * k);
    poses.push_back(pose);
  }
  const std::vector<int> section_of = {0, 0, 0, 0, 0, 1, 1, 1, 2, 2, 2, 2};
  const std::vector<bool> straight = {true, false, true};
  std::vector<bool> confirmed(12, true);
  confirmed[10] = false;
  TIntersectionRecord t;
  t.section = 1;
  t.red_keyframe = 3;
  t.blue_keyframe = 8;
  LoopClosurePassOptions options;
  options.t_step_rotation_sigma_deg = 5.0;
  options.t_turn_sigma_deg = 0.5;
  options.t_turn_huber_sigmas = 1.0;
  const std::vector<PoseGraphEdge> edges =
      OdometryGraphEdges(poses, section_of, straight, confirmed, {t}, options);
  ASSERT_EQ(edges.size(), 12u);  // 11 steps and the T's turn
  const double deg = M_PI / 180.0;
  const auto rotation_sigma = [](const PoseGraphEdge& e) { return 1.0 / std::sqrt(e.information(5, 5)); };
  const auto translation_sigma = [](const PoseGraphEdge& e) { return 1.0 / std::sqrt(e.information(0, 0)); };
  for (int k = 0; k < 11; ++k) {
    const PoseGraphEdge& step = edges[k];
    EXPECT_EQ(step.from, k);
    EXPECT_EQ(step.to, k + 1);
    EXPECT_EQ(step.huber_scale, 0.0);
    EXPECT_TRUE(step.from_T_to.isApprox(poses[k].inverse() * poses[k + 1], 1e-12)) << k;
    const bool in_t = k + 1 >= 5 && k + 1 <= 7;
    const double factor = k + 1 == 10 ? options.unconfirmed_step_factor : 1.0;
    EXPECT_NEAR(rotation_sigma(step),
                in_t ? options.t_step_rotation_sigma_deg * deg
                     : factor * options.step_rotation_sigma_deg * deg,
                1e-12)
        << k;
    EXPECT_NEAR(translation_sigma(step), factor * options.step_translation_sigma_m, 1e-12) << k;
  }
  const PoseGraphEdge& turn = edges.back();
  EXPECT_EQ(turn.from, 3);
  EXPECT_EQ(turn.to, 8);
  EXPECT_TRUE(turn.from_T_to.isApprox(poses[3].inverse() * poses[8], 1e-12));
  EXPECT_NEAR(rotation_sigma(turn), options.t_turn_sigma_deg * deg, 1e-12);
  EXPECT_EQ(turn.huber_scale, options.t_turn_huber_sigmas);

  // Without a turn sigma, no turn edge.
  LoopClosurePassOptions without_turn = options;
  without_turn.t_turn_sigma_deg = 0.0;
  EXPECT_EQ(OdometryGraphEdges(poses, section_of, straight, confirmed, {t}, without_turn).size(),
            11u);
  // A T record without key frames (a route that ends in its T) adds no edge.
  TIntersectionRecord unplaced;
  unplaced.red_keyframe = 9;
  unplaced.blue_keyframe = 12;
  EXPECT_EQ(OdometryGraphEdges(poses, section_of, straight, confirmed, {unplaced}, options).size(),
            11u);
}

// A passage straight through a junction knows its path there, not where along it the centre
// lies: the gap to it counts only the part across that path. Route B's first passage of T1 put
// its centre (the T section's middle key frame) 0.121 m along the pipe from the true centre.
TEST(LoopClosurePass, AStraightThroughPassageCountsOnlyTheGapAcrossItsPath) {
  PassageCentre turned;  // an adjusted T's centre
  turned.point = Eigen::Vector3d(1.0, 2.0, 3.0);
  PassageCentre through;
  through.point = turned.point + Eigen::Vector3d(0.121, 0.003, -0.004);
  through.straight_through = true;
  through.through_direction = Eigen::Vector3d::UnitX();
  EXPECT_NEAR(PassageGap(turned, through), 0.005, 1e-12);
  EXPECT_NEAR(PassageGap(through, turned), 0.005, 1e-12);

  // Two turned passages: the whole distance.
  PassageCentre other = turned;
  other.point += Eigen::Vector3d(0.121, 0.003, -0.004);
  EXPECT_NEAR(PassageGap(turned, other), std::sqrt(0.121 * 0.121 + 0.000025), 1e-12);

  // Both straight through, along different directions: the larger distance across.
  PassageCentre through_y = through;
  through_y.point = turned.point;
  through_y.through_direction = Eigen::Vector3d::UnitY();
  // Across x: |(0.003, -0.004)| = 0.005; across y: |(0.121, -0.004)|.
  EXPECT_NEAR(PassageGap(through, through_y), std::hypot(0.121, 0.004), 1e-12);
}

}  // namespace
}  // namespace pipescope
