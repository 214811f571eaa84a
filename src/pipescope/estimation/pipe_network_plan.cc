#include "pipescope/estimation/pipe_network_plan.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include "pipescope/util/error.h"

namespace pipescope {
namespace {

// Where along the pipe (0..length) the point's foot lies, and how far off the axis it is.
struct OnPipe {
  double along_m;
  double off_axis_m;
};

OnPipe Project(const PlanPipe& pipe, const Eigen::Vector3d& point) {
  const Eigen::Vector3d axis = pipe.end - pipe.start;
  const double length = axis.norm();
  const double along = std::clamp((point - pipe.start).dot(axis / length), 0.0, length);
  return {along, (pipe.start + along * axis / length - point).norm()};
}

// A node of the network: a tee, or a pipe end (a dead end, or a joint of two pipes).
struct Node {
  Eigen::Vector3d position;
  int tee = -1;
};

// The node at `position` (within `tolerance_m`), added when there is none.
int NodeAt(const Eigen::Vector3d& position, double tolerance_m, std::vector<Node>* nodes) {
  for (int n = 0; n < static_cast<int>(nodes->size()); ++n) {
    if (((*nodes)[n].position - position).norm() <= tolerance_m) return n;
  }
  nodes->push_back({position, -1});
  return static_cast<int>(nodes->size()) - 1;
}

std::string PipeName(int p) { return "pipe " + std::to_string(p); }

}  // namespace

PlannedNetwork BuildPlannedNetwork(const PipePlan& plan) {
  if (!(plan.start_heading.norm() > 0.0) || !plan.start_heading.allFinite()) {
    throw InputError("the plan's start heading must be a non-zero vector");
  }
  std::vector<Node> nodes;
  for (int t = 0; t < static_cast<int>(plan.tees.size()); ++t) {
    nodes.push_back({plan.tees[t].center, t});
  }
  std::vector<bool> tee_on_a_pipe(plan.tees.size(), false);
  PlannedNetwork result;
  std::vector<std::array<int, 2>> section_nodes;
  for (int p = 0; p < static_cast<int>(plan.pipes.size()); ++p) {
    const PlanPipe& pipe = plan.pipes[p];
    const double length = (pipe.end - pipe.start).norm();
    if (!(length > 0.0) || !(pipe.radius_m > 0.0)) {
      throw InputError(PipeName(p) + " of the plan has no length or no radius");
    }
    // The pipe's breaks: its ends and the tees on it, in order along it.
    std::vector<std::pair<double, int>> breaks;
    for (int t = 0; t < static_cast<int>(plan.tees.size()); ++t) {
      const OnPipe on = Project(pipe, plan.tees[t].center);
      if (on.off_axis_m > pipe.radius_m) continue;
      breaks.emplace_back(on.along_m, t);
      tee_on_a_pipe[t] = true;
    }
    const Eigen::Vector3d direction = (pipe.end - pipe.start) / length;
    for (const double along : {0.0, length}) {
      const int node = NodeAt(pipe.start + along * direction, pipe.radius_m, &nodes);
      if (std::none_of(breaks.begin(), breaks.end(),
                       [&](const auto& entry) { return entry.second == node; })) {
        breaks.emplace_back(along, node);
      }
    }
    std::sort(breaks.begin(), breaks.end());
    for (std::size_t b = 0; b + 1 < breaks.size(); ++b) {
      if (breaks[b + 1].first - breaks[b].first <= pipe.radius_m) continue;  // one node
      PlannedSection section;
      for (int e = 0; e < 2; ++e) {
        const int node = breaks[b + e].second;
        section.end_point[e] = nodes[node].position;
        section.tee_at_end[e] = nodes[node].tee;
      }
      result.sections.push_back(section);
      section_nodes.push_back({breaks[b].second, breaks[b + 1].second});
    }
  }
  for (int t = 0; t < static_cast<int>(plan.tees.size()); ++t) {
    if (!tee_on_a_pipe[t]) {
      throw InputError("tee " + plan.tees[t].name + " of the plan lies on no pipe");
    }
  }
  const int sections = static_cast<int>(result.sections.size());
  result.network.section_ends.resize(sections);
  for (int s = 0; s < sections; ++s) {
    for (int e = 0; e < 2; ++e) {
      const PlannedSection& in = result.sections[s];
      const Eigen::Vector3d arriving = in.end_point[e] - in.end_point[1 - e];
      SectionEndExits& exits = result.network.section_ends[s][e];
      for (int s2 = 0; s2 < sections; ++s2) {
        for (int e2 = 0; e2 < 2; ++e2) {
          if ((s2 == s && e2 == e) || section_nodes[s2][e2] != section_nodes[s][e]) continue;
          const PlannedSection& out = result.sections[s2];
          const int turn =
              TurnDirection(arriving, out.end_point[1 - e2] - out.end_point[e2], plan.up);
          SectionExit& exit = turn > 0 ? exits.left : turn < 0 ? exits.right : exits.straight;
          if (exit.section >= 0) {
            throw InputError("the plan has two ways " +
                             std::string(turn > 0   ? "left"
                                         : turn < 0 ? "right"
                                                    : "straight") +
                             " out of the node at end " + std::to_string(e) + " of section " +
                             std::to_string(s));
          }
          exit = {s2, e2};
        }
      }
    }
  }
  double nearest = std::numeric_limits<double>::infinity();
  for (int s = 0; s < sections; ++s) {
    const PlannedSection& section = result.sections[s];
    const PlanPipe piece{section.end_point[0], section.end_point[1], 1.0};
    const double distance = Project(piece, plan.start_position).off_axis_m;
    if (distance < nearest) {
      nearest = distance;
      const Eigen::Vector3d along = section.end_point[1] - section.end_point[0];
      result.start = {s, plan.start_heading.dot(along) > 0.0 ? 1 : 0};
    }
  }
  if (sections == 0) throw InputError("the plan has no pipes");
  return result;
}

}  // namespace pipescope
