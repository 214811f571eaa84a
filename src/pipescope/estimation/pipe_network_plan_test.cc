#include "pipescope/estimation/pipe_network_plan.h"

#include <gtest/gtest.h>

#include <vector>

#include "pipescope/util/error.h"

namespace pipescope {
namespace {

using Eigen::Vector3d;

constexpr double kSideM = 8.15;
constexpr double kStubM = 1.5;
constexpr double kRadiusM = 0.2;

// The simulator's square loop in the X-Y plane, up +Z: side i runs from T_i (where it leaves as a
// branch) through T_{i+1} (as that T's through run) on to T_{i+1}'s dead-end arm.
const std::vector<Vector3d> kTees = {
    {0, 0, 0}, {0, kSideM, 0}, {-kSideM, kSideM, 0}, {-kSideM, 0, 0}};

PipePlan SquareLoopPlan() {
  PipePlan plan;
  plan.up = Vector3d::UnitZ();
  for (int i = 0; i < 4; ++i) {
    const Vector3d& from = kTees[i];
    const Vector3d& to = kTees[(i + 1) % 4];
    plan.pipes.push_back({from, to + kStubM * (to - from).normalized(), kRadiusM});
    plan.tees.push_back({"T" + std::to_string(i + 1), kTees[i]});
  }
  // The start: in T1's dead-end arm, heading for T1.
  const Vector3d d41 = (kTees[0] - kTees[3]).normalized();
  plan.start_position = kTees[0] + 1.2 * d41;
  plan.start_heading = -d41;
  return plan;
}

// True when `point` lies on the section (within 1 mm of its axis, between its ends).
bool OnSection(const PlannedSection& section, const Vector3d& point) {
  const Vector3d axis = section.end_point[1] - section.end_point[0];
  const double along = (point - section.end_point[0]).dot(axis) / axis.squaredNorm();
  const Vector3d foot = section.end_point[0] + along * axis;
  return along > -1e-9 && along < 1 + 1e-9 && (foot - point).norm() < 1e-3;
}

// Drives a route through `waypoints` (start, junctions, end) on the plan's network: the
// sections named by counting turns must hold each leg's two ends, in the direction driven.
void ExpectRouteFollowsWaypoints(const std::vector<Vector3d>& waypoints) {
  const PipePlan plan = SquareLoopPlan();
  const PlannedNetwork planned = BuildPlannedNetwork(plan);
  std::vector<int> turns;
  for (std::size_t k = 1; k + 1 < waypoints.size(); ++k) {
    turns.push_back(
        TurnDirection(waypoints[k] - waypoints[k - 1], waypoints[k + 1] - waypoints[k], plan.up));
  }
  const std::vector<SectionPass> passes = NameSectionPasses(planned.network, planned.start, turns);
  ASSERT_EQ(passes.size(), waypoints.size() - 1);
  for (std::size_t k = 0; k < passes.size(); ++k) {
    const PlannedSection& section = planned.sections[passes[k].section];
    // Each leg ends at the pass's far end (a junction), or lies within the section (the last).
    const Vector3d& from = waypoints[k];
    const Vector3d& to = waypoints[k + 1];
    EXPECT_TRUE(OnSection(section, from)) << "leg " << k;
    EXPECT_TRUE(OnSection(section, to)) << "leg " << k;
    const Vector3d toward =
        section.end_point[passes[k].toward_end] - section.end_point[1 - passes[k].toward_end];
    EXPECT_GT(toward.dot(to - from), 0.0) << "leg " << k;
  }
}

TEST(PipeNetworkPlan, SplitsThePipesAtTheirTeesIntoEightSections) {
  const PlannedNetwork planned = BuildPlannedNetwork(SquareLoopPlan());
  ASSERT_EQ(planned.sections.size(), 8u);  // four sides and four dead-end arms
  int dead_ends = 0;
  for (const PlannedSection& section : planned.sections) {
    dead_ends += (section.tee_at_end[0] < 0) + (section.tee_at_end[1] < 0);
  }
  EXPECT_EQ(dead_ends, 4);
  // The start lies in T1's arm, heading for T1.
  const PlannedSection& start = planned.sections[planned.start.section];
  EXPECT_EQ(start.tee_at_end[planned.start.toward_end], 0);
  EXPECT_LT(start.tee_at_end[1 - planned.start.toward_end], 0);
}

TEST(PipeNetworkPlan, RouteAAroundTheLoopIsNamedByItsTurns) {
  const Vector3d d41 = (kTees[0] - kTees[3]).normalized();
  ExpectRouteFollowsWaypoints(
      {kTees[0] + 1.2 * d41, kTees[0], kTees[1], kTees[2], kTees[3], kTees[0] - 1.0 * d41});
}

TEST(PipeNetworkPlan, RouteBThroughT1AndTheLoopTheOtherWayIsNamedByItsTurns) {
  const Vector3d d41 = (kTees[0] - kTees[3]).normalized();
  const Vector3d d34 = (kTees[3] - kTees[2]).normalized();
  // Straight through T1 is a junction passed too: a turn of 0.
  ExpectRouteFollowsWaypoints({kTees[0] + 1.2 * d41, kTees[0], kTees[3], kTees[2], kTees[1],
                               kTees[0], kTees[3], kTees[3] + 1.0 * d34});
}

TEST(PipeNetworkPlan, UpsideDownSwapsLeftAndRight) {
  PipePlan plan = SquareLoopPlan();
  const PlannedNetwork up = BuildPlannedNetwork(plan);
  plan.up = -plan.up;
  const PlannedNetwork down = BuildPlannedNetwork(plan);
  for (std::size_t s = 0; s < up.sections.size(); ++s) {
    for (int e = 0; e < 2; ++e) {
      EXPECT_EQ(up.network.section_ends[s][e].left.section,
                down.network.section_ends[s][e].right.section);
      EXPECT_EQ(up.network.section_ends[s][e].straight.section,
                down.network.section_ends[s][e].straight.section);
    }
  }
}

TEST(PipeNetworkPlan, BadPlansAreRefusedByName) {
  PipePlan plan = SquareLoopPlan();
  plan.tees.push_back({"T9", {50, 50, 0}});
  EXPECT_THROW(
      {
        try {
          BuildPlannedNetwork(plan);
        } catch (const InputError& error) {
          EXPECT_NE(std::string(error.what()).find("T9"), std::string::npos);
          throw;
        }
      },
      InputError);
  plan = SquareLoopPlan();
  plan.pipes[2].end = plan.pipes[2].start;
  EXPECT_THROW(BuildPlannedNetwork(plan), InputError);
  plan = SquareLoopPlan();
  plan.start_heading = Vector3d::Zero();
  EXPECT_THROW(BuildPlannedNetwork(plan), InputError);
}

}  // namespace
}  // namespace pipescope
