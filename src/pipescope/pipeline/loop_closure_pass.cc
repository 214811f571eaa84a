#include "pipescope/pipeline/loop_closure_pass.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <unordered_map>
#include <utility>

#include "pipescope/estimation/pass_consensus.h"
#include "pipescope/estimation/pipe_network_plan.h"
#include "pipescope/estimation/place_ambiguity.h"
#include "pipescope/feature/descriptor_matching.h"
#include "pipescope/feature/sift_description.h"
#include "pipescope/geometry/bearing_pnp.h"
#include "pipescope/geometry/clock_position.h"
#include "pipescope/io/image_source.h"
#include "pipescope/pipeline/pipe_plan_yaml.h"
#include "pipescope/util/error.h"

namespace pipescope {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

// The straight sections in the order driven, and the T section between each two (-1: none).
struct SectionOrder {
  std::vector<int> straight;
  std::vector<int> t_between;  // t_between[i] lies between straight[i] and straight[i + 1]
};

SectionOrder OrderSections(const std::vector<bool>& section_straight) {
  SectionOrder order;
  int pending_t = -1;
  for (int s = 0; s < static_cast<int>(section_straight.size()); ++s) {
    if (!section_straight[s]) {
      pending_t = s;
      continue;
    }
    if (!order.straight.empty()) order.t_between.push_back(pending_t);
    order.straight.push_back(s);
    pending_t = -1;
  }
  return order;
}

// The direction of travel over about `path_m` of a section's key frames, at its end (`at_end`)
// or its start.
Eigen::Vector3d PathDirection(const std::vector<int>& keyframes,
                              const std::vector<Eigen::Isometry3d>& world_from_cam, bool at_end,
                              double path_m) {
  const int n = static_cast<int>(keyframes.size());
  const int anchor = at_end ? n - 1 : 0;
  const int step = at_end ? -1 : 1;
  int other = anchor;
  double path = 0.0;
  while (other + step >= 0 && other + step < n && path < path_m) {
    path += (world_from_cam[keyframes[other + step]].translation() -
             world_from_cam[keyframes[other]].translation())
                .norm();
    other += step;
  }
  const Eigen::Vector3d d = world_from_cam[keyframes[anchor]].translation() -
                            world_from_cam[keyframes[other]].translation();
  return at_end ? d : Eigen::Vector3d(-d);
}

// A passage whose travel lines before and after lie within 20 deg of parallel went straight
// through its junction.
bool PassesStraightThrough(const Eigen::Vector3d& direction_in,
                           const Eigen::Vector3d& direction_out) {
  const double b = direction_in.normalized().dot(direction_out.normalized());
  return 1.0 - b * b < std::pow(std::sin(20.0 * kDegToRad), 2);
}

// Where the path turns at a T the model did not place: the midpoint of the closest approach of
// the travel lines before and after it; for lines within 20 deg of parallel (a pass straight
// through), the T section's middle key frame. Loop candidates only need the two passes' views to
// overlap: the relative pose is measured on the images.
Eigen::Vector3d PathCorner(const Eigen::Vector3d& end_before, const Eigen::Vector3d& direction_in,
                           const Eigen::Vector3d& start_after, const Eigen::Vector3d& direction_out,
                           const Eigen::Vector3d& t_middle) {
  if (PassesStraightThrough(direction_in, direction_out)) return t_middle;
  const Eigen::Vector3d u = direction_in.normalized(), v = direction_out.normalized();
  const double b = u.dot(v);
  const Eigen::Vector3d w = end_before - start_after;
  const double s = (b * v.dot(w) - u.dot(w)) / (1.0 - b * b);
  const double t = (v.dot(w) - b * u.dot(w)) / (1.0 - b * b);
  return 0.5 * ((end_before + s * u) + (start_after + t * v));
}

// A key frame of an earlier pass, to be matched against the later pass `later_pass`.
struct Candidate {
  int earlier_keyframe;
  int later_pass;
};

// A key frame's tracked features: their bearings, their map points in the key frame's camera
// frame (NaN where the track has none) and their SIFT descriptors.
struct KeyframeView {
  std::vector<Eigen::Vector3d> bearings;
  std::vector<Eigen::Vector3d> points_in_camera;
  cv::Mat descriptors;
};

KeyframeView DescribeKeyframe(const LoopClosureInput& input, const LoopClosurePassOptions& options,
                              const std::unordered_map<long, Eigen::Vector3d>& point_of_track,
                              int k, const Eigen::Isometry3d& world_from_cam, const cv::Mat& grey) {
  std::vector<long> ids;
  const auto tracks = input.odometry.TracksIn(k, k, 1, &ids);
  const Eigen::Isometry3d cam_from_world = world_from_cam.inverse();
  const float margin = 6.0f * options.descriptor_size_px;
  KeyframeView view;
  std::vector<Keypoint> keypoints;
  for (std::size_t t = 0; t < tracks.size(); ++t) {
    const Eigen::Vector2d& pixel = tracks[t].front().pixel;
    if (pixel.x() < margin || pixel.y() < margin || pixel.x() > grey.cols - 1 - margin ||
        pixel.y() > grey.rows - 1 - margin) {
      continue;
    }
    Eigen::Vector3d in_camera = Eigen::Vector3d::Constant(std::nan(""));
    const auto point = point_of_track.find(ids[t]);
    if (point != point_of_track.end()) in_camera = cam_from_world * point->second;
    // Far points' depth is the least certain.
    if (in_camera.norm() > options.max_point_range_radii * input.radius_m) {
      in_camera = Eigen::Vector3d::Constant(std::nan(""));
    }
    keypoints.push_back({cv::Point2f(pixel.x(), pixel.y()), 0.f});
    view.bearings.push_back(tracks[t].front().bearing);
    view.points_in_camera.push_back(in_camera);
  }
  if (!keypoints.empty()) {
    view.descriptors = DescribeWithSift(grey, keypoints, {options.descriptor_size_px});
  }
  return view;
}

// The later key frame placed against the earlier one's map points (PnP on its bearings): the
// later pass's own scale, which its odometry may have lost, plays no part.
LoopEdgeRecord MeasureEdge(int earlier_keyframe, int later_keyframe, const KeyframeView& earlier,
                           const KeyframeView& later, double radius_m,
                           const LoopClosurePassOptions& options) {
  LoopEdgeRecord edge;
  edge.earlier_keyframe = earlier_keyframe;
  edge.later_keyframe = later_keyframe;
  if (earlier.descriptors.empty() || later.descriptors.empty()) {
    edge.rejection = "no described points";
    return edge;
  }
  const std::vector<IndexMatch> matches = MatchDescriptors(earlier.descriptors, later.descriptors,
                                                           {options.max_descriptor_ratio, true});
  std::vector<Eigen::Vector3d> points, bearings;
  for (const IndexMatch& match : matches) {
    if (!earlier.points_in_camera[match.first].allFinite()) continue;
    points.push_back(earlier.points_in_camera[match.first]);
    bearings.push_back(later.bearings[match.second]);
  }
  edge.matches = static_cast<int>(points.size());
  BearingPnpOptions pnp_options;
  pnp_options.max_angle_deg = options.max_angle_deg;
  const BearingPnp pnp = SolveBearingPnp(points, bearings, pnp_options);
  edge.inliers = static_cast<int>(pnp.inliers.size());
  edge.rms_deg = pnp.rms_deg;
  edge.earlier_from_later = pnp.cam_from_points.inverse();
  const double turn_deg = Eigen::AngleAxisd(edge.earlier_from_later.linear()).angle() / kDegToRad;
  if (!pnp.found || edge.inliers < options.min_inliers) {
    edge.rejection = "too few inliers";
  } else if (edge.earlier_from_later.translation().norm() > radius_m) {
    edge.rejection = "the two key frames more than a radius apart";
  } else if (turn_deg > options.max_edge_rotation_deg) {
    edge.rejection = "the two key frames turned by " + std::to_string(turn_deg) + " deg";
  } else {
    edge.accepted = true;
  }
  return edge;
}

// One passage of the run through a junction: the T between two straight sections.
struct Passage {
  int keyframe_before = 0;  // the straight section's last key frame before it
  int t_record = -1;        // the adjusted T's record, -1: none
  int tee = -1;             // the plan's tee, -1: a dead end
  PassageCentre centre;
};

double LargestGap(const std::vector<Passage>& passages, const std::vector<int>& indices) {
  double gap = 0.0;
  for (int a : indices) {
    for (int b : indices) gap = std::max(gap, PassageGap(passages[a].centre, passages[b].centre));
  }
  return gap;
}

}  // namespace

double PassageGap(const PassageCentre& a, const PassageCentre& b) {
  const Eigen::Vector3d d = b.point - a.point;
  const auto across = [&d](const Eigen::Vector3d& direction) {
    return (d - d.dot(direction) * direction).norm();
  };
  if (a.straight_through && b.straight_through) {
    return std::max(across(a.through_direction), across(b.through_direction));
  }
  if (a.straight_through) return across(a.through_direction);
  if (b.straight_through) return across(b.through_direction);
  return d.norm();
}

std::vector<PoseGraphEdge> OdometryGraphEdges(const std::vector<Eigen::Isometry3d>& world_from_cam,
                                             const std::vector<int>& section_of,
                                             const std::vector<bool>& section_straight,
                                             const std::vector<bool>& step_confirmed,
                                             const std::vector<TIntersectionRecord>& t_intersections,
                                             const LoopClosurePassOptions& options) {
  const int keyframe_count = static_cast<int>(world_from_cam.size());
  std::vector<PoseGraphEdge> edges =
      ConsecutivePoseEdges(world_from_cam, options.step_translation_sigma_m,
                           options.step_rotation_sigma_deg * kDegToRad);
  const Eigen::Matrix<double, 6, 6> t_step_information = IsotropicPoseInformation(
      options.step_translation_sigma_m, options.t_step_rotation_sigma_deg * kDegToRad);
  const Eigen::Matrix<double, 6, 6> unconfirmed_step_information = IsotropicPoseInformation(
      options.unconfirmed_step_factor * options.step_translation_sigma_m,
      options.unconfirmed_step_factor * options.step_rotation_sigma_deg * kDegToRad);
  for (PoseGraphEdge& edge : edges) {
    if (!section_straight[section_of[edge.to]]) {
      edge.information = t_step_information;
    } else if (!step_confirmed[edge.to]) {
      edge.information = unconfirmed_step_information;
    }
  }
  // Each T's turn, as one edge: only its rotation, since its steps carry the translation (1 m
  // here constrains nothing beside their 1 mm each).
  if (options.t_turn_sigma_deg <= 0.0) return edges;
  const Eigen::Matrix<double, 6, 6> t_turn_information =
      IsotropicPoseInformation(1.0, options.t_turn_sigma_deg * kDegToRad);
  for (const TIntersectionRecord& t : t_intersections) {
    if (t.red_keyframe < 0 || t.red_keyframe >= t.blue_keyframe ||
        t.blue_keyframe >= keyframe_count) {
      continue;
    }
    PoseGraphEdge turn{t.red_keyframe, t.blue_keyframe,
                       world_from_cam[t.red_keyframe].inverse() * world_from_cam[t.blue_keyframe],
                       t_turn_information};
    turn.huber_scale = options.t_turn_huber_sigmas;
    edges.push_back(turn);
  }
  return edges;
}

LoopClosureRecord CloseLoops(const LoopClosureInput& input, const LoopClosurePassOptions& options,
                             std::vector<Eigen::Isometry3d>* world_from_cam,
                             std::vector<TIntersectionRecord>* t_intersections,
                             std::vector<SparsePoint>* points) {
  LoopClosureRecord record;
  if (input.manifest.scene_path.empty() || !input.manifest.pipe_up) {
    record.why_not =
        "the dataset has no plan of the network (scene.yaml with route_start, and pipe.up)";
    return record;
  }
  std::optional<PipePlan> plan =
      ReadPipePlan(input.manifest.scene_path, *input.manifest.pipe_up, &record.why_not);
  if (!plan) return record;
  const PlannedNetwork planned = BuildPlannedNetwork(*plan);

  // The turns at the Ts between straight sections, in the map's frame about the camera's
  // upright (the crawler drives upright; pipe.up says the same in the plan's frame).
  const int keyframe_count = static_cast<int>(world_from_cam->size());
  std::vector<std::vector<int>> keyframes_of_section(input.section_straight.size());
  for (int k = 0; k < keyframe_count; ++k) keyframes_of_section[input.section_of[k]].push_back(k);
  const SectionOrder order = OrderSections(input.section_straight);
  std::vector<PassageCentre> corners;  // per T between straight sections
  for (std::size_t i = 0; i + 1 < order.straight.size(); ++i) {
    const std::vector<int>& before = keyframes_of_section[order.straight[i]];
    const std::vector<int>& after = keyframes_of_section[order.straight[i + 1]];
    const Eigen::Vector3d up = CameraUpright((*world_from_cam)[before.back()].linear());
    const Eigen::Vector3d in =
        PathDirection(before, *world_from_cam, true, options.turn_direction_path_m);
    const Eigen::Vector3d out =
        PathDirection(after, *world_from_cam, false, options.turn_direction_path_m);
    record.turns.push_back(TurnDirection(in, out, up));
    const int t_section = order.t_between[i];
    const std::vector<int>& t_keyframes = t_section >= 0 ? keyframes_of_section[t_section] : before;
    PassageCentre corner;
    corner.point = PathCorner((*world_from_cam)[before.back()].translation(), in,
                              (*world_from_cam)[after.front()].translation(), out,
                              (*world_from_cam)[t_keyframes[t_keyframes.size() / 2]].translation());
    corner.straight_through = PassesStraightThrough(in, out);
    corner.through_direction = (in.normalized() + out.normalized()).normalized();
    corners.push_back(corner);
  }
  try {
    record.passes = NameSectionPasses(planned.network, planned.start, record.turns);
  } catch (const InputError& error) {
    record.why_not = std::string("the run's turns do not fit the plan: ") + error.what();
    return record;
  }

  // Each junction passage's centre: the adjusted T's, else the path's corner there; each pass's
  // junctions are the passages before and after it.
  std::map<int, int> t_record_of_section;
  for (int r = 0; r < static_cast<int>(t_intersections->size()); ++r) {
    const TIntersectionRecord& t = (*t_intersections)[r];
    if (t.rejection.empty()) t_record_of_section[t.section] = r;
  }
  std::vector<Passage> passages;
  for (std::size_t i = 0; i + 1 < order.straight.size(); ++i) {
    Passage passage;
    passage.keyframe_before = keyframes_of_section[order.straight[i]].back();
    const auto found = t_record_of_section.find(order.t_between[i]);
    passage.t_record = found == t_record_of_section.end() ? -1 : found->second;
    if (passage.t_record >= 0) {
      passage.centre.point = (*t_intersections)[passage.t_record].geometry.centre;
    } else {
      passage.centre = corners[i];
    }
    const SectionPass& pass = record.passes[i];
    passage.tee = planned.sections[pass.section].tee_at_end[pass.toward_end];
    passages.push_back(passage);
  }
  std::map<int, std::vector<int>> passages_of_tee;
  std::vector<std::vector<int>> revisit_passages;  // per revisit
  for (int i = 0; i < static_cast<int>(passages.size()); ++i) {
    if (passages[i].tee >= 0) passages_of_tee[passages[i].tee].push_back(i);
  }
  for (const auto& [tee, indices] : passages_of_tee) {
    if (indices.size() < 2) continue;
    JunctionRevisit revisit;
    revisit.name = plan->tees[tee].name;
    for (int i : indices) revisit.t_sections.push_back(order.t_between[i]);
    revisit.gap_before_m = revisit.gap_after_m = LargestGap(passages, indices);
    revisit.across_path_only = std::any_of(indices.begin(), indices.end(), [&](int i) {
      return passages[i].centre.straight_through;
    });
    for (int k = passages[indices.front()].keyframe_before;
         k < passages[indices.back()].keyframe_before; ++k) {
      revisit.path_between_m +=
          ((*world_from_cam)[k + 1].translation() - (*world_from_cam)[k].translation()).norm();
    }
    record.revisits.push_back(revisit);
    revisit_passages.push_back(indices);
  }
  std::vector<int> pass_of_keyframe(keyframe_count, -1);  // index into order.straight
  std::vector<Eigen::Vector3d> positions;
  for (int k = 0; k < keyframe_count; ++k) {
    positions.push_back((*world_from_cam)[k].translation());
    const auto at = std::find(order.straight.begin(), order.straight.end(), input.section_of[k]);
    if (at != order.straight.end())
      pass_of_keyframe[k] = static_cast<int>(at - order.straight.begin());
  }
  if (!options.enabled) {
    record.why_not = "loop_closure is off (the revisits are still measured)";
    return record;
  }
  // Candidates: for every two passes of one section driven the same way, key frames spread
  // evenly along the earlier pass, each to be matched against the whole later pass (below).
  // 001 pairs key frames at equal distances from the junction at the section's end; where one
  // pass's odometry lost its scale (route B's second T1-T4 pass: 1.3 m for 3 m) those pairs
  // see different wall, and all of them lie at the junction's end of the section.
  const int straight_passes = static_cast<int>(order.straight.size());
  std::vector<std::vector<int>> keyframes_of_pass(straight_passes);
  for (int k = 0; k < keyframe_count; ++k) {
    if (pass_of_keyframe[k] >= 0) keyframes_of_pass[pass_of_keyframe[k]].push_back(k);
  }
  std::vector<Candidate> candidates;
  for (int a = 0; a < straight_passes; ++a) {
    for (int b = a + 1; b < straight_passes; ++b) {
      if (record.passes[a].section != record.passes[b].section) continue;
      if (record.passes[a].toward_end != record.passes[b].toward_end) {
        record.unmatched_reverse_passes.push_back({a, b});  // the wall seen from the other side
        continue;
      }
      const std::vector<int>& earlier = keyframes_of_pass[a];
      const int count = std::min<int>(options.max_pairs, earlier.size());
      for (int c = 0; c < count; ++c) {
        candidates.push_back({earlier[(2 * c + 1) * earlier.size() / (2 * count)], b});
      }
    }
  }
  if (candidates.empty()) {
    record.why_not = "no section was driven twice the same way";
    return record;
  }

  // The later pass is searched over its whole length, a key frame every search_step_m of path.
  std::map<int, std::vector<int>> samples_of_pass;
  for (const Candidate& candidate : candidates) {
    const int pass = candidate.later_pass;
    if (samples_of_pass.count(pass)) continue;
    std::vector<int>& samples = samples_of_pass[pass];
    double path = options.search_step_m;
    for (int k = 0; k < keyframe_count; ++k) {
      if (pass_of_keyframe[k] != pass) continue;
      if (!samples.empty()) path += (positions[k] - positions[k - 1]).norm();
      if (path < options.search_step_m) continue;
      samples.push_back(k);
      path = 0.0;
    }
  }
  std::set<int> wanted_keyframes;
  for (const Candidate& candidate : candidates) wanted_keyframes.insert(candidate.earlier_keyframe);
  for (const auto& [pass, samples] : samples_of_pass) {
    wanted_keyframes.insert(samples.begin(), samples.end());
  }
  std::unordered_map<int, int> keyframe_of_frame;
  for (int k : wanted_keyframes) keyframe_of_frame[input.frame_index[k]] = k;
  std::unordered_map<long, Eigen::Vector3d> point_of_track;
  for (const SparsePoint& point : *points) {
    if (point.track_id >= 0) point_of_track[point.track_id] = point.position;
  }
  ImageSourceOptions source_options{input.camera.Width(), input.camera.Height()};
  source_options.wanted = [&](std::size_t index) {
    return keyframe_of_frame.count(static_cast<int>(index)) > 0;
  };
  std::map<int, KeyframeView> views;
  auto source = ImageSource::Open(input.manifest, source_options);
  while (std::optional<Frame> frame = source->Next()) {
    const auto found = keyframe_of_frame.find(static_cast<int>(frame->index));
    if (found == keyframe_of_frame.end()) continue;
    views[found->second] = DescribeKeyframe(input, options, point_of_track, found->second,
                                            (*world_from_cam)[found->second], frame->grey);
  }
  std::vector<PoseGraphEdge> edges =
      OdometryGraphEdges(*world_from_cam, input.section_of, input.section_straight,
                         input.step_confirmed, *t_intersections, options);
  const Eigen::Matrix<double, 6, 6> loop_information = IsotropicPoseInformation(
      options.loop_translation_sigma_m, options.loop_rotation_sigma_deg * kDegToRad);
  std::vector<double> path_along_pass(keyframe_count, 0.0);
  for (int k = 1; k < keyframe_count; ++k) {
    if (pass_of_keyframe[k] >= 0 && pass_of_keyframe[k] == pass_of_keyframe[k - 1]) {
      path_along_pass[k] = path_along_pass[k - 1] + (positions[k] - positions[k - 1]).norm();
    }
  }
  const double ambiguity_separation_m = options.ambiguity_separation_radii * input.radius_m;
  for (const Candidate& candidate : candidates) {
    LoopEdgeRecord best;
    best.earlier_keyframe = candidate.earlier_keyframe;
    best.rejection = "frame not read";
    // Every place of the later pass that gave an edge, and its key frame.
    std::vector<PlaceMatch> places;
    std::vector<int> place_keyframes;
    const auto earlier = views.find(candidate.earlier_keyframe);
    for (const int later : samples_of_pass[candidate.later_pass]) {
      const auto view = views.find(later);
      if (earlier == views.end() || view == views.end()) continue;
      const LoopEdgeRecord edge = MeasureEdge(candidate.earlier_keyframe, later, earlier->second,
                                              view->second, input.radius_m, options);
      if (edge.accepted) {
        places.push_back({path_along_pass[later], edge.inliers});
        place_keyframes.push_back(later);
      }
      if (best.rejection == "frame not read" || (edge.accepted && !best.accepted) ||
          (edge.accepted == best.accepted && edge.inliers > best.inliers)) {
        best = edge;
      }
    }
    // The best place must stand out from every place far enough from it to be another one.
    if (best.accepted) {
      const int best_place = static_cast<int>(
          std::find(place_keyframes.begin(), place_keyframes.end(), best.later_keyframe) -
          place_keyframes.begin());
      const PlaceJudgement judgement =
          JudgeBestPlace(places, best_place, ambiguity_separation_m, options.max_runner_up_share);
      if (judgement.runner_up >= 0) {
        best.runner_up_keyframe = place_keyframes[judgement.runner_up];
        best.runner_up_inliers = places[judgement.runner_up].inliers;
      }
      if (judgement.ambiguous) {
        char apart[32];
        std::snprintf(apart, sizeof(apart), "%.2f",
                      std::abs(places[judgement.runner_up].path_m - places[best_place].path_m));
        best.accepted = false;
        best.rejection = std::string("another place ") + apart +
                         " m along the later pass matches about as well (a repeated pattern)";
      }
    }
    record.edges.push_back(best);
  }
  // Only edges that agree with each other along the two passes (a wall pattern repeating along
  // the pipe gives confirmed edges metres apart).
  for (LoopEdgeRecord& edge : record.edges) edge.path_m = path_along_pass[edge.earlier_keyframe];
  std::map<std::pair<int, int>, std::vector<int>> accepted_of_passes;
  for (int e = 0; e < static_cast<int>(record.edges.size()); ++e) {
    const LoopEdgeRecord& edge = record.edges[e];
    if (!edge.accepted) continue;
    accepted_of_passes[{pass_of_keyframe[edge.earlier_keyframe],
                        pass_of_keyframe[edge.later_keyframe]}]
        .push_back(e);
  }
  int accepted = 0;
  for (const auto& [pass_pair, indices] : accepted_of_passes) {
    std::vector<double> earlier_path, later_path;
    for (int e : indices) {
      earlier_path.push_back(path_along_pass[record.edges[e].earlier_keyframe]);
      later_path.push_back(path_along_pass[record.edges[e].later_keyframe]);
    }
    std::vector<int> agreeing = ConsistentLoopEdges(earlier_path, later_path);
    if (static_cast<int>(agreeing.size()) < options.min_agreeing_edges) agreeing.clear();
    for (int i = 0; i < static_cast<int>(indices.size()); ++i) {
      LoopEdgeRecord& edge = record.edges[indices[i]];
      if (std::find(agreeing.begin(), agreeing.end(), i) == agreeing.end()) {
        edge.accepted = false;
        edge.rejection = agreeing.empty()
                             ? "fewer than " + std::to_string(options.min_agreeing_edges) +
                                   " edges of the two passes agree"
                             : "off the line of the other edges (a repeated pattern)";
        continue;
      }
      edges.push_back(
          {edge.earlier_keyframe, edge.later_keyframe, edge.earlier_from_later, loop_information});
      ++accepted;
    }
  }
  if (accepted == 0) {
    record.why_not = "no loop candidate gave a relative pose";
    return record;
  }

  const std::vector<Eigen::Isometry3d> before = *world_from_cam;
  record.graph = OptimisePoseGraph(edges, world_from_cam, options.graph);
  record.applied = true;
  // The structure moves with the key frames (001 §III-E): each point with the key frame that
  // first saw it, each T with its P_r.
  const auto correction = [&](int k) { return (*world_from_cam)[k] * before[k].inverse(); };
  for (SparsePoint& point : *points) {
    int k = point.track_id >= 0 ? input.odometry.FirstKeyframeOfTrack(point.track_id) : -1;
    if (k < 0)
      k = keyframes_of_section[point.section].empty() ? 0
                                                      : keyframes_of_section[point.section].front();
    point.position = correction(k) * point.position;
  }
  for (TIntersectionRecord& t : *t_intersections) {
    if (t.blue_keyframe < static_cast<int>(before.size())) {
      const Eigen::Matrix3d turn_before =
          before[t.red_keyframe].linear().transpose() * before[t.blue_keyframe].linear();
      const Eigen::Matrix3d turn_after = (*world_from_cam)[t.red_keyframe].linear().transpose() *
                                         (*world_from_cam)[t.blue_keyframe].linear();
      record.t_turn_changes.push_back(
          {t.section,
           Eigen::AngleAxisd(turn_before.transpose() * turn_after).angle() / kDegToRad});
    }
    const Eigen::Isometry3d c = correction(t.red_keyframe);
    t.geometry.centre = c * t.geometry.centre;
    t.geometry.red_direction = c.linear() * t.geometry.red_direction;
    t.geometry.blue_direction = c.linear() * t.geometry.blue_direction;
    t.geometry.world_from_blue_camera = c * t.geometry.world_from_blue_camera;
  }
  for (Passage& passage : passages) {
    if (passage.t_record >= 0) {
      passage.centre.point = (*t_intersections)[passage.t_record].geometry.centre;
    } else {
      const Eigen::Isometry3d c = correction(passage.keyframe_before);
      passage.centre.point = c * passage.centre.point;
      passage.centre.through_direction = c.linear() * passage.centre.through_direction;
    }
  }
  for (std::size_t r = 0; r < record.revisits.size(); ++r) {
    record.revisits[r].gap_after_m = LargestGap(passages, revisit_passages[r]);
  }
  return record;
}

namespace {

double RevisitGap(const LoopClosureRecord& record, const JunctionRevisit& revisit) {
  return record.applied ? revisit.gap_after_m : revisit.gap_before_m;
}

}  // namespace

bool RevisitHolds(const LoopClosureRecord& record, const JunctionRevisit& revisit,
                  double max_gap_share) {
  return RevisitGap(record, revisit) <= max_gap_share * revisit.path_between_m;
}

std::vector<std::string> RevisitReasons(const LoopClosureRecord& record, double max_gap_share) {
  std::vector<std::string> reasons;
  for (const JunctionRevisit& revisit : record.revisits) {
    if (RevisitHolds(record, revisit, max_gap_share)) continue;
    reasons.push_back("the run passed junction " + revisit.name + " " +
                      std::to_string(revisit.t_sections.size()) + " times and placed it up to " +
                      std::to_string(RevisitGap(record, revisit)) + " m apart" +
                      (revisit.across_path_only ? " (across the straight-through path)" : "") +
                      " over " +
                      std::to_string(revisit.path_between_m) + " m of path" +
                      (record.applied ? " after loop closure" : " (no loop closure)"));
  }
  return reasons;
}

}  // namespace pipescope
