#pragma once

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "pipescope/camera/camera.h"
#include "pipescope/estimation/keyframe_odometry.h"
#include "pipescope/estimation/loop_candidates.h"  // SectionPass
#include "pipescope/estimation/pose_graph.h"
#include "pipescope/io/dataset.h"
#include "pipescope/pipeline/t_intersection_pass.h"

namespace pipescope {

// 001 §III-E after the T-intersections: the network's plan (the dataset's scene.yaml with its
// route_start, pipeline/pipe_plan_yaml.h) and the turns the run took name the section of every
// straight pass; key frames spread along the earlier of two passes of one section are each
// matched against the later pass's key frames (SIFT at their tracked corners), the best placed
// against the earlier's map points (PnP with RANSAC on the bearings) if no other place matches
// about as well (estimation/place_ambiguity.h), and the edges that agree along the passes kept
// (estimation/pass_consensus.h); a pose
// graph over every key frame (odometry edges and the accepted loop edges, Ceres) moves the key
// frames, and their points and junctions move with them.
struct LoopClosurePassOptions {
  // On by default since the seventeenth session: on route B's first 4400 frames every edge it
  // applied paired places within 5 cm of each other on three seeds (default, 41 and 43; 43 never
  // tuned on), where before the place test (ambiguity_separation_radii) the default seed's
  // consensus took five edges one wall repeat (1 m) off (docs/fisheye_mapping.md). A route that
  // drives no section twice has nothing to close. Off, the passes are still named and the
  // revisits measured.
  bool enabled = true;
  int max_pairs = 15;  // key frames along the earlier of two passes; 001 closed its loop with 15
  // Turns: the travel directions over this much path before and after a T.
  double turn_direction_path_m = 1.0;
  float descriptor_size_px = 8.0f;  // SIFT keypoint diameter: the described patch ~7 times it
  double max_descriptor_ratio = 0.8;
  // Map points farther than this many radii from the camera are left out: their depth is the
  // least certain.
  double max_point_range_radii = 5.0;
  // Each candidate's earlier key frame is matched against the later pass's key frames this far
  // apart along its path, and the one with the most inliers is kept.
  double search_step_m = 0.1;
  // A place that matches about as well as the best one farther along the later pass than
  // `ambiguity_separation_radii` radii (with `max_runner_up_share` of its inliers or more) makes
  // the candidate ambiguous, and it is refused: on a wall that repeats (painted rings, joints) the
  // best match is as often the wrong repeat as the right place. On route B's default seed the
  // consensus of five edges one repeat (1 m) off outvoted three right ones
  // (docs/fisheye_mapping.md).
  double ambiguity_separation_radii = 2.5;
  double max_runner_up_share = 0.8;
  double max_angle_deg = 0.5;  // PnP: a bearing farther off its point is an outlier
  int min_inliers = 20;
  // Of two passes' confirmed edges, at least this many must agree on where the passes overlap
  // (estimation/pass_consensus.h), or none is used.
  int min_agreeing_edges = 3;
  // A loop edge joins two key frames of one pipe at one distance from its junction: they are
  // within a radius of each other and turned by less than this, or the edge is refused.
  double max_edge_rotation_deg = 20.0;
  // The pose graph's edges (standard deviations on every axis): odometry steps; loop edges.
  // A straight step's rotation sigma is set by what its errors add up to over a section, not by
  // one step's (route B's 4400 frames, bench/fisheye_step_errors.py: 0.074 deg RMS a step, but
  // 0.34 deg over 400 steps, where independent errors would give 1.5 deg; 0.01 deg a step gives
  // 0.2 deg over 400), so that a closure cannot bend a straight section more cheaply than it
  // turns a corner. The translation's 1 mm is loose (0.05-0.06 mm RMS a step, along and across),
  // but 0.1 mm moved no T-to-T distance by more than 0.05 % on the two seeds replayed, with this
  // graph or the one before (docs/fisheye_mapping.md).
  double step_translation_sigma_m = 0.001;
  double step_rotation_sigma_deg = 0.01;
  // Inside a T section a step's rotation has t_step_rotation_sigma_deg: a T's angle is what the
  // map knows least well. Each T's turn, P_r to P_b as the T pass left it, is also one edge of
  // its own (t_turn_sigma_deg above 0) with Huber's loss beyond t_turn_huber_sigmas (0:
  // squared), so that a loop that must close puts one wrong corner's error on that corner
  // instead of spreading it over all. What a closure cannot see (on a four-T loop, a shear of the
  // corners, +t -t +t -t, keeps the loop closed) is then set by the robust loss's preference for
  // few wrong corners rather than by an even spread. Chosen on route B's 4400 frames (default
  // seed; replayed offline, bench/pose_graph_replay.py) and checked on seed 43: the six T-to-T
  // distances 0.373 and 0.064 % off at worst, against 0.622 and 0.367 % with squared errors
  // and every T step at 0.5 deg (docs/fisheye_mapping.md, "Where a closure bends the path").
  double t_step_rotation_sigma_deg = 1.0;
  double t_turn_sigma_deg = 0.5;
  double t_turn_huber_sigmas = 0.5;
  // A straight step no applied window confirmed rests on the single step's scale and rotation
  // (docs/fisheye_mapping.md: such sections came out up to 57 % short): both its sigmas times
  // this.
  double unconfirmed_step_factor = 20.0;
  double loop_translation_sigma_m = 0.005;
  double loop_rotation_sigma_deg = 0.5;
  PoseGraphOptions graph;
};

// One loop candidate and what became of it.
struct LoopEdgeRecord {
  int earlier_keyframe = 0;
  int later_keyframe = 0;  // the later pass's key frame that matched best
  double path_m = 0.0;     // the earlier key frame's place along its pass
  int matches = 0;
  int inliers = 0;
  double rms_deg = 0.0;  // PnP's inliers: bearing against the earlier key frame's point
  // The best other place along the later pass (ambiguity_separation_radii from this one): its
  // key frame (-1: none matched) and inliers.
  int runner_up_keyframe = -1;
  int runner_up_inliers = 0;
  bool accepted = false;
  std::string rejection;
  Eigen::Isometry3d earlier_from_later = Eigen::Isometry3d::Identity();
};

// A junction the run passed more than once: where each passage put its centre (the adjusted
// T's, else the corner of the path there), the largest distance between them before and after
// the closure (the return error, 001 §IV-A).
struct JunctionRevisit {
  std::string name;             // the plan's tee
  std::vector<int> t_sections;  // the T section of each passage, in the order passed
  double gap_before_m = 0.0;
  double gap_after_m = 0.0;     // after the closure; equal to gap_before_m when none was applied
  double path_between_m = 0.0;  // key frame path from the first passage's P_r to the last's
  // A passage straight through the junction does not say where along its path the centre lies
  // (nothing turns there), so the gaps then count only the distance across that path.
  bool across_path_only = false;
};

// Where one passage put a junction's centre. A passage straight through it (no turn) knows its
// path there, not the centre's place along it: `point` is then the T section's middle key frame
// and `through_direction` the path's direction.
struct PassageCentre {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  bool straight_through = false;
  Eigen::Vector3d through_direction = Eigen::Vector3d::UnitZ();
};

// The distance between two passages' centres of one junction, counting for a straight-through
// passage only the part across its path (both straight through: the larger of the two).
double PassageGap(const PassageCentre& a, const PassageCentre& b);

// How much the closure turned one T: the rotation between its P_r and P_b after the closure
// against before it. The closure changes a corner's angle where the graph lets it; these tell
// the user which corners took the correction.
struct TTurnChange {
  int section = 0;  // the T section
  double turn_change_deg = 0.0;
};

struct LoopClosureRecord {
  bool applied = false;
  std::string why_not;              // when not applied
  std::vector<int> turns;           // per T section passed: +1 left, -1 right, 0 straight
  std::vector<SectionPass> passes;  // per straight section, its section of the plan
  std::vector<std::pair<int, int>> unmatched_reverse_passes;  // driven the other way: not matched
  std::vector<LoopEdgeRecord> edges;
  std::vector<JunctionRevisit> revisits;
  std::vector<TTurnChange> t_turn_changes;  // per T record, when the closure was applied
  PoseGraphResult graph;
};

// The key frames (`world_from_cam`, `section_of` into `sections` with `section_straight`), the
// T records and the points are moved in place when loop edges were accepted. Throws InputError
// when the dataset's scene.yaml is malformed.
struct LoopClosureInput {
  const DatasetManifest& manifest;
  const Camera& camera;
  const KeyframeOdometry& odometry;
  double radius_m = 0.0;
  std::vector<int> frame_index;  // per key frame
  std::vector<int> section_of;   // per key frame
  std::vector<bool> section_straight;
  std::vector<bool> step_confirmed;  // per key frame: an applied window spans the step into it
};

// The pose graph's edges before any loop edge: one per odometry step between consecutive key
// frames of `world_from_cam` (a straight step's sigmas, times unconfirmed_step_factor where no
// applied window confirmed it, `step_confirmed` per key frame; a T section's steps with
// t_step_rotation_sigma_deg), then one per T record from its P_r to its P_b, measuring the turn
// between them with t_turn_sigma_deg and Huber's loss beyond t_turn_huber_sigmas.
std::vector<PoseGraphEdge> OdometryGraphEdges(const std::vector<Eigen::Isometry3d>& world_from_cam,
                                             const std::vector<int>& section_of,
                                             const std::vector<bool>& section_straight,
                                             const std::vector<bool>& step_confirmed,
                                             const std::vector<TIntersectionRecord>& t_intersections,
                                             const LoopClosurePassOptions& options);

LoopClosureRecord CloseLoops(const LoopClosureInput& input, const LoopClosurePassOptions& options,
                             std::vector<Eigen::Isometry3d>* world_from_cam,
                             std::vector<TIntersectionRecord>* t_intersections,
                             std::vector<SparsePoint>* points);

// Whether the run placed a revisited junction's passages within `max_gap_share` of the path
// between them (after the closure, if one was applied).
bool RevisitHolds(const LoopClosureRecord& record, const JunctionRevisit& revisit,
                  double max_gap_share = 0.01);

// What a run's revisits say of it: each junction whose passages still lie more than
// `max_gap_share` of the path between them apart (after the closure, if one was applied) is a
// reason the run is unreliable: the map disagrees with itself there.
std::vector<std::string> RevisitReasons(const LoopClosureRecord& record,
                                        double max_gap_share = 0.01);

}  // namespace pipescope
