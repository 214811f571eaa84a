#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <optional>
#include <vector>

namespace pipescope {

// 001 §III-E picks loop closures without place recognition: knowing the section of the pipe
// network the robot starts in and counting its left/right turns at the junctions names the
// straight section of every pass, and key frames P_i, P_j of two passes of the same section are
// a candidate pair when their distances l_i, l_j to the centroid I of the junction at the end of
// the section agree.

// +1 for a left turn, -1 for a right one, 0 for straight through (the axes within
// `straight_below_rad` of each other): the sign of (axis_in x axis_out) . up. The axes are the
// travel directions along the pipes before and after the junction; `up` is the side the turns
// are seen from (the robot's up). Throws InputError for a zero or non-finite vector.
int TurnDirection(const Eigen::Vector3d& axis_in, const Eigen::Vector3d& axis_out,
                  const Eigen::Vector3d& up, double straight_below_rad = M_PI / 4.0);

// Where the robot goes from one end of a section: into `section` (-1: there is no pipe that
// way) through that section's end `entered_end` (0 or 1).
struct SectionExit {
  int section = -1;
  int entered_end = 0;
};

// The ways on from one end of a section, as seen arriving at that end.
struct SectionEndExits {
  SectionExit left;
  SectionExit straight;
  SectionExit right;
};

// A pipe network as straight sections joined at junctions: for each section, the exits at its
// end 0 and end 1. A dead end has no exits.
struct PipeNetwork {
  std::vector<std::array<SectionEndExits, 2>> section_ends;
};

// One drive along a straight section, towards its end `toward_end`.
struct SectionPass {
  int section = -1;
  int toward_end = 1;
};

// The section of every pass of a run that starts with the pass `start` and turns `turns`
// (TurnDirection's +1, 0, -1) at the junctions in order: turns.size() + 1 passes. Throws
// InputError naming the turn when it leads into no pipe, or when a section or turn is invalid.
std::vector<SectionPass> NameSectionPasses(const PipeNetwork& network, const SectionPass& start,
                                           const std::vector<int>& turns);

// A pass as the odometry has it: its section and direction, and the centroids I of the junctions
// at its start and end (001 §III-D's T-intersection centroid), both in the frame of this pass's
// own pose estimates; nullopt where the pass starts or ends at none (a dead end, the run's end).
struct PassJunctions {
  SectionPass pass;
  std::optional<Eigen::Vector3d> start_centroid;
  std::optional<Eigen::Vector3d> end_centroid;
};

struct LoopCandidateOptions {
  // |l_i - l_j| must be within max(tolerance_m, tolerance_fraction * l_i).
  double tolerance_m = 0.005;
  double tolerance_fraction = 0.0;
  // At most this many pairs per two passes of a section, spread evenly along the stretch both
  // passes cover; 001 §IV-A closed its loop with 15.
  int max_pairs = 15;
};

// Key frames `earlier` and `later` (indices into the run's key frames, earlier < later) are in
// the same section on two passes, at distances `earlier_distance_m`, `later_distance_m` from the
// centroid of the same junction.
struct LoopCandidate {
  int earlier = -1;
  int later = -1;
  double earlier_distance_m = 0.0;
  double later_distance_m = 0.0;
};

// Candidate pairs between every two passes of the same section. `key_frame_positions[k]` is key
// frame k's position and `key_frame_pass[k]` its index into `passes` (-1: in no straight pass,
// e.g. inside a junction). For each two passes, the junction both know a centroid of is the
// reference, the end of the earlier pass first; each key frame of the earlier pass within the
// stretch both passes cover is matched to the key frame of the later pass nearest in distance,
// and kept when the distances agree within the tolerance. Ordered by passes, then by distance.
// Throws InputError when the sizes differ or a pass index is out of range.
std::vector<LoopCandidate> SelectLoopCandidates(
    const std::vector<Eigen::Vector3d>& key_frame_positions, const std::vector<int>& key_frame_pass,
    const std::vector<PassJunctions>& passes, const LoopCandidateOptions& options = {});

}  // namespace pipescope
