#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "pipescope/estimation/loop_candidates.h"

namespace pipescope {

// A plan of a pipe network, as a user draws it from the network's drawings (or the simulator
// writes it in scene.yaml): straight pipes, the T-intersections on them, which way is up, and
// where the robot started. Loop closure (001 §III-E) takes only its topology from it: which
// pipe a turn at a junction leads into. Its lengths are never used as measurements.
struct PlanPipe {
  Eigen::Vector3d start = Eigen::Vector3d::Zero();
  Eigen::Vector3d end = Eigen::Vector3d::Zero();
  double radius_m = 0.0;
};

struct PlanTee {
  std::string name;
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
};

struct PipePlan {
  std::vector<PlanPipe> pipes;
  std::vector<PlanTee> tees;
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();  // the robot's up in the plan's frame
  Eigen::Vector3d start_position = Eigen::Vector3d::Zero();
  Eigen::Vector3d start_heading = Eigen::Vector3d::UnitX();
};

// One section of the network: a stretch of pipe between two nodes (a tee or a dead end).
struct PlannedSection {
  Eigen::Vector3d end_point[2];
  int tee_at_end[2] = {-1, -1};  // index into PipePlan::tees, -1: a dead end
};

struct PlannedNetwork {
  PipeNetwork network;                   // exits per section end (loop_candidates.h)
  std::vector<PlannedSection> sections;  // the same indices
  SectionPass start;                     // the pass the robot started in
};

// Splits every pipe at the tees that lie on it (within the pipe's radius of its axis, between
// its ends) and joins the pieces at the tees: arriving at a tee along a section, each other
// section there is a left, straight or right exit by TurnDirection (straight below 45 deg) about
// `plan.up`. The start pass is the section nearest plan.start_position, towards the end that
// plan.start_heading points to. Throws InputError naming the pipe or tee when a pipe has no
// length, a tee lies on no pipe, two exits of one end take the same way, or the heading is zero.
PlannedNetwork BuildPlannedNetwork(const PipePlan& plan);

}  // namespace pipescope
