#include "pipescope/pipeline/t_intersection_pass.h"

#include <algorithm>
#include <cmath>
#include <opencv2/core/utility.hpp>
#include <optional>
#include <unordered_set>

#include "pipescope/geometry/multiview_triangulation.h"
#include "pipescope/pipeline/section_cylinder.h"

namespace pipescope {
namespace {

constexpr double kDeg = M_PI / 180.0;

Eigen::Vector3d Centre(const Eigen::Isometry3d& world_from_cam) {
  return world_from_cam.translation();
}

// A track's point from its observations (multi-view midpoint on the bearings), when its rays
// part by at least `min_angle_rad` from its first. `world_from_cam[k]` is key frame
// `first_keyframe + k`'s pose.
bool Triangulate(const std::vector<KeyframeOdometry::Observation>& observations,
                 const std::vector<Eigen::Isometry3d>& world_from_cam, int first_keyframe,
                 double min_angle_rad, Eigen::Vector3d* point) {
  const auto pose_of = [&](const KeyframeOdometry::Observation& observation) -> const auto& {
    return world_from_cam[observation.keyframe - first_keyframe];
  };
  const Eigen::Vector3d first_ray =
      pose_of(observations.front()).linear() * observations.front().bearing;
  std::vector<BearingObservation> rays;
  double widest = 0.0;
  for (const KeyframeOdometry::Observation& observation : observations) {
    const Eigen::Isometry3d& pose = pose_of(observation);
    rays.push_back({pose.inverse(), observation.bearing});
    widest = std::max(widest, std::acos(std::clamp(
                                  first_ray.dot(pose.linear() * observation.bearing), -1.0, 1.0)));
  }
  return widest >= min_angle_rad && TriangulateMidpoint(rays, point);
}

double PathLength(const std::vector<Eigen::Isometry3d>& world_from_cam, int first, int last) {
  double length = 0.0;
  for (int k = first; k < last; ++k) {
    length += (Centre(world_from_cam[k + 1]) - Centre(world_from_cam[k])).norm();
  }
  return length;
}

// The share `w` of a rigid move G that keeps `pivot` (G's image of it moves by w) and turns by
// w of G's rotation: G_w(x) = R_w (x - pivot) + pivot + w (G(pivot) - pivot).
Eigen::Isometry3d PartialMove(const Eigen::Isometry3d& move, const Eigen::Vector3d& pivot,
                              double w) {
  const Eigen::Quaterniond turn =
      Eigen::Quaterniond::Identity().slerp(w, Eigen::Quaterniond(move.linear()));
  Eigen::Isometry3d partial = Eigen::Isometry3d::Identity();
  partial.linear() = turn.toRotationMatrix();
  partial.translation() = pivot - partial.linear() * pivot + w * (move * pivot - pivot);
  return partial;
}

}  // namespace

std::vector<TIntersectionRecord> TIntersectionPass::Run(
    const KeyframeOdometry& odometry, const std::vector<int>& section_of,
    const std::vector<PipeViewClass>& classes, const std::vector<double>& timestamps,
    std::vector<Eigen::Isometry3d>* world_from_cam, std::vector<SparsePoint>* points) const {
  std::vector<TIntersectionRecord> records;
  if (!options_.enabled) return records;
  const int num_keyframes = static_cast<int>(world_from_cam->size());
  const double lead_m = options_.red_lead_radii * options_.adjustment.radius_m;
  for (int s = 1; s + 1 < static_cast<int>(classes.size()); ++s) {
    if (classes[s] != PipeViewClass::kTIntersection || classes[s - 1] != PipeViewClass::kStraight ||
        classes[s + 1] != PipeViewClass::kStraight) {
      continue;
    }
    const auto first_of = [&](int section) {
      return static_cast<int>(std::find(section_of.begin(), section_of.end(), section) -
                              section_of.begin());
    };
    const int red_last = first_of(s) - 1;
    const int blue = first_of(s + 1);
    if (red_last < 0 || blue >= num_keyframes) continue;
    // P_r held at `red`; the last and first metre of travel of the two straight sections
    // before P_r and after P_b (001 Fig. 4a).
    const auto span_from = [&](int red) {
      TSpan span;
      span.section = s;
      span.red = red;
      span.red_last = red_last;
      span.blue = blue;
      span.red_start = red;
      while (span.red_start > 0 && section_of[span.red_start - 1] == s - 1 &&
             PathLength(*world_from_cam, span.red_start - 1, red) <= options_.end_fit_length_m) {
        --span.red_start;
      }
      span.blue_end = blue;
      while (span.blue_end + 1 < num_keyframes && section_of[span.blue_end + 1] == s + 1 &&
             PathLength(*world_from_cam, blue, span.blue_end + 1) <= options_.end_fit_length_m) {
        ++span.blue_end;
      }
      return span;
    };
    // P_r red_lead_radii before the T, as long as the red section keeps min_end_length_m of
    // travel before it to fit its end cylinder to.
    int red_first = red_last;
    while (red_first > 0 && section_of[red_first - 1] == s - 1) --red_first;
    int red = red_last;
    while (red > red_first && PathLength(*world_from_cam, red, red_last) < lead_m &&
           PathLength(*world_from_cam, red_first, red - 1) >= options_.min_end_length_m) {
      --red;
    }
    records.push_back(AdjustOne(odometry, span_from(red), span_from(red_last), timestamps, *points,
                                world_from_cam));
    const TIntersectionRecord& t = records.back();
    if (!t.rejection.empty()) continue;
    *points = MergeTIntersectionPoints(std::move(*points), s, t);
  }
  return records;
}

std::vector<SparsePoint> MergeTIntersectionPoints(std::vector<SparsePoint> points, int section,
                                                  const TIntersectionRecord& t) {
  const std::unordered_set<long> replaced(t.point_tracks.begin(), t.point_tracks.end());
  std::vector<SparsePoint> merged;
  for (SparsePoint& point : points) {
    if (point.section == section || (point.track_id >= 0 && replaced.count(point.track_id) > 0)) {
      continue;
    }
    if (point.section > section) point.position = t.correction * point.position;
    merged.push_back(point);
  }
  for (std::size_t p = 0; p < t.points.size(); ++p) {
    merged.push_back({t.points[p], section, p < t.point_tracks.size() ? t.point_tracks[p] : -1});
  }
  return merged;
}

TIntersectionPass::TTracks TIntersectionPass::TracksOf(const KeyframeOdometry& odometry, int red,
                                                       int blue) {
  TTracks tracks;
  tracks.observations = odometry.TracksIn(red, blue, 2, &tracks.ids);
  return tracks;
}

double TIntersectionPass::FitEndCylinder(const std::vector<SparsePoint>& points, int section,
                                         int origin, int far,
                                         const std::vector<Eigen::Isometry3d>& world_from_cam,
                                         double cylinder[4], int* count) const {
  // Only the points beside this stretch of pipe, none on the T's side of the origin camera:
  // the cameras see into the T, whose walls are not this cylinder's. A radius of slack on the
  // far side.
  const Eigen::Vector3d far_centre = Centre(world_from_cam[far]);
  if ((far_centre - Centre(world_from_cam[origin])).norm() < options_.min_end_length_m) {
    return -1.0;
  }
  const double radius = options_.adjustment.radius_m;
  const std::optional<SectionCylinderFit> fit =
      FitSectionCylinder(points, section, world_from_cam[origin], far_centre, radius, radius);
  if (!fit) return -1.0;
  *count = fit->points;
  std::copy(fit->cylinder, fit->cylinder + 4, cylinder);
  return fit->median_distance_m;
}

TIntersectionPass::StartedAdjustment TIntersectionPass::AdjustFromScale(
    const TTracks& tracks, const TSpan& span, const std::vector<Eigen::Isometry3d>& poses,
    const TIntersectionProblem& cylinders, double scale, double phi_offset_deg) const {
  StartedAdjustment started;
  started.scale = scale;
  started.phi_offset_deg = phi_offset_deg;
  std::copy(cylinders.red_cylinder, cylinders.red_cylinder + 4, started.problem.red_cylinder);
  std::copy(cylinders.blue_cylinder, cylinders.blue_cylinder + 4, started.problem.blue_cylinder);
  TIntersectionProblem& problem = started.problem;
  const int red = span.red, blue = span.blue;
  // The chained T scaled about the red section's last key frame (the straight stretch before it
  // keeps its length) ...
  std::vector<Eigen::Isometry3d> start(poses.begin() + red, poses.begin() + blue + 1);
  const Eigen::Vector3d pivot_red = Centre(poses[span.red_last]);
  for (std::size_t k = span.red_last - red + 1; k < start.size(); ++k) {
    Eigen::Isometry3d& pose = start[k];
    pose.translation() = pivot_red + scale * (Centre(pose) - pivot_red);
  }
  const auto model = FitTIntersectionModel(start.front(), problem.red_cylinder, start.back(),
                                           problem.blue_cylinder, options_.min_turn_deg * kDeg);
  int observations = 0;
  for (const auto& track : tracks.observations) observations += static_cast<int>(track.size());
  const double cap_px = 3.0;  // about where the MAD stages cut
  started.score = observations * cap_px * cap_px;
  if (!model) return started;
  std::copy(model->data(), model->data() + kTIntersectionParameters, problem.model);
  problem.model[kPhi] = std::clamp(problem.model[kPhi] + phi_offset_deg * kDeg,
                                   options_.min_turn_deg * kDeg, M_PI - options_.min_turn_deg * kDeg);
  if (options_.fitting_angle_deg > 0.0) {
    const double given = options_.fitting_angle_deg * kDeg;
    const double chained = problem.model[kPhi];
    problem.model[kPhi] =
        std::abs(given - chained) <= std::abs(M_PI - given - chained) ? given : M_PI - given;
  }
  // ... then each pose takes the share of the move from there to where the model puts P_b that
  // its path fraction says.
  const Eigen::Isometry3d to_model = TIntersectionInWorld(start.front(), problem.red_cylinder,
                                                          problem.blue_cylinder, problem.model)
                                         .world_from_blue_camera *
                                     start.back().inverse();
  const int last = static_cast<int>(start.size()) - 1;
  // The path fractions on the scaled chain, before any pose moves.
  std::vector<double> fraction(start.size(), 0.0);
  const double length = std::max(1e-9, PathLength(start, 0, last));
  for (int k = 1; k <= last; ++k) fraction[k] = PathLength(start, 0, k) / length;
  const Eigen::Vector3d pivot = Centre(start.back());
  for (int k = 1; k <= last; ++k) start[k] = PartialMove(to_model, pivot, fraction[k]) * start[k];
  for (const Eigen::Isometry3d& pose : start) {
    problem.poses.push_back(WindowPose::FromIsometry(pose.inverse()));
  }
  for (std::size_t t = 0; t < tracks.observations.size(); ++t) {
    const std::vector<KeyframeOdometry::Observation>& track = tracks.observations[t];
    Eigen::Vector3d point;
    if (!Triangulate(track, start, red, options_.min_triangulation_angle_deg * kDeg, &point)) {
      continue;
    }
    const int index = static_cast<int>(problem.points.size());
    problem.points.push_back(point);
    started.point_tracks.push_back(tracks.ids[t]);
    for (const KeyframeOdometry::Observation& observation : track) {
      const bool inlier =
          ReprojectionErrorPx(camera_, problem.poses[observation.keyframe - red].ToIsometry(),
                              point, observation.pixel) < options_.max_start_error_px;
      problem.observations.push_back(
          {observation.keyframe - red, index, observation.pixel, inlier});
    }
  }
  if (problem.points.size() < 20) return started;
  TIntersectionOptions adjustment = options_.adjustment;
  adjustment.hold_phi = options_.fitting_angle_deg > 0.0;
  started.summary = OptimiseTIntersection(camera_, adjustment, &problem);
  if (!started.summary.usable) return started;
  // The score: every observation of the T's tracks, its error capped, so that the starts
  // compare on the same observations whatever each kept as inliers or triangulated.
  started.score = 0.0;
  int scored = 0;
  for (const WindowObservation& observation : problem.observations) {
    const Eigen::Isometry3d cam_from_world = observation.pose == last
                                                 ? BlueCamFromWorld(problem)
                                                 : problem.poses[observation.pose].ToIsometry();
    const double error = ReprojectionErrorPx(camera_, cam_from_world,
                                             problem.points[observation.point], observation.pixel);
    started.score += std::min(error, cap_px) * std::min(error, cap_px);
    ++scored;
  }
  started.score += (observations - scored) * cap_px * cap_px;
  return started;
}

bool TIntersectionPass::StartModel(const TSpan& span, const std::vector<SparsePoint>& points,
                                   const std::vector<Eigen::Isometry3d>& poses,
                                   TIntersectionProblem* problem,
                                   TIntersectionRecord* record) const {
  const double radius = options_.adjustment.radius_m;
  record->red_fit_m = FitEndCylinder(points, span.section - 1, span.red, span.red_start, poses,
                                     problem->red_cylinder, &record->red_fit_points);
  record->blue_fit_m = FitEndCylinder(points, span.section + 1, span.blue, span.blue_end, poses,
                                      problem->blue_cylinder, &record->blue_fit_points);
  if (record->red_fit_m < 0.0 || record->blue_fit_m < 0.0) {
    record->rejection = "short section";  // too little travel or fewer than 20 points beside it
    return false;
  }
  if (std::max(record->red_fit_m, record->blue_fit_m) >= options_.max_cylinder_rms * radius) {
    record->rejection = "end cylinder";
    return false;
  }
  const auto initial = FitTIntersectionModel(poses[span.red], problem->red_cylinder,
                                             poses[span.blue], problem->blue_cylinder,
                                             options_.min_turn_deg * kDeg, &record->axis_gap_m);
  if (!initial) {
    record->rejection = "no turn";
    return false;
  }
  std::copy(initial->data(), initial->data() + kTIntersectionParameters, problem->model);
  std::copy(initial->data(), initial->data() + kTIntersectionParameters, record->initial_model);
  return true;
}

std::optional<TIntersectionPass::StartedAdjustment> TIntersectionPass::BestStart(
    const KeyframeOdometry& odometry, const TSpan& span,
    const std::vector<Eigen::Isometry3d>& poses, const TIntersectionProblem& cylinders,
    const std::vector<std::pair<double, double>>& scale_and_phi, const char* stage,
    TIntersectionRecord* record) const {
  // Each start ends in a minimum of its own: the chain through a T took its step lengths from
  // the straight section's axis, which the T's walls do not follow, so its length is off (10-11 %
  // short on the simulated network), and its turn may be (11.6 degrees at route A's T2, seed
  // 41); an adjustment started there stays in that basin. So the starts are several, and the
  // solution that explains the T's images best is kept.
  const TTracks tracks = TracksOf(odometry, span.red, span.blue);
  // The starts are independent: they run on OpenCV's workers (both cores are free once the
  // tracking is done), each into its own slot, so the choice does not depend on the threads.
  const int num_starts = static_cast<int>(scale_and_phi.size());
  std::vector<StartedAdjustment> starts(num_starts);
  cv::parallel_for_(
      cv::Range(0, num_starts),
      [&](const cv::Range& range) {
        for (int i = range.start; i < range.end; ++i) {
          starts[i] = AdjustFromScale(tracks, span, poses, cylinders, scale_and_phi[i].first,
                                      scale_and_phi[i].second);
        }
      },
      num_starts);
  std::optional<StartedAdjustment> best;
  for (StartedAdjustment& started : starts) {
    record->start_scores.push_back({stage, started.scale, started.phi_offset_deg, started.score,
                                    started.problem.model[kPhi] / kDeg});
    if (!best || started.score < best->score) best = std::move(started);
  }
  if (!best || best->problem.points.size() < 20) return std::nullopt;
  return best;
}

TIntersectionRecord TIntersectionPass::AdjustOne(
    const KeyframeOdometry& odometry, const TSpan& span, const TSpan& choice,
    const std::vector<double>& timestamps, const std::vector<SparsePoint>& points,
    std::vector<Eigen::Isometry3d>* world_from_cam) const {
  const int section = span.section, red = span.red, blue = span.blue;
  const int red_start = span.red_start, blue_end = span.blue_end;
  TIntersectionRecord record;
  record.section = section;
  record.red_keyframe = red;
  record.blue_keyframe = blue;
  const double radius = options_.adjustment.radius_m;
  std::vector<Eigen::Isometry3d>& poses = *world_from_cam;

  TIntersectionProblem problem;
  if (!StartModel(span, points, poses, &problem, &record)) return record;
  const auto place = [&](const double model[kTIntersectionParameters]) {
    record.modelled = true;
    std::copy(model, model + kTIntersectionParameters, record.model);
    record.geometry =
        TIntersectionInWorld(poses[red], problem.red_cylinder, problem.blue_cylinder, model);
    double nearest = 1e300;
    for (int k = red_start; k <= blue_end; ++k) {
      const double distance = (Centre(poses[k]) - record.geometry.centre).norm();
      if (distance < nearest) {
        nearest = distance;
        record.timestamp = timestamps[k];
      }
    }
  };
  if (record.axis_gap_m > options_.max_axis_gap_radii * radius) {
    record.rejection = "axes miss";  // no centre: the two axes do not meet
    return record;
  }
  place(problem.model);

  // The scale is chosen on the T from its red section's last key frame: seven adjustments of
  // the T alone cost a third of those with the half metre before it, and the scale they choose
  // is that of the same stretch (scaled about that key frame either way). Phi is not: from
  // there the red end cylinder is fitted relative to a key frame the straight windows left
  // turned, and on route A's T2 (seed 41) the turned starts scored worse than the chained one
  // on the short T (60 481 against 52 466 at 12 degrees less) and better on the whole one
  // (64 001 against 75 995); on the whole route phi came out 88.8 degrees, not 97.1, for a tee
  // whose pipes meet at 90.3. So
  // the T with P_r red_lead_radii before it is adjusted from the chosen scale at the chained
  // phi and at each turned one.
  TIntersectionProblem choice_problem;
  TIntersectionRecord choice_record;
  const bool choose_on_short =
      choice.red != span.red && StartModel(choice, points, poses, &choice_problem, &choice_record);
  std::vector<std::pair<double, double>> scales;
  for (double scale : options_.start_scales) scales.emplace_back(scale, 0.0);
  std::optional<StartedAdjustment> best =
      choose_on_short ? BestStart(odometry, choice, poses, choice_problem, scales, "scale", &record)
                      : BestStart(odometry, span, poses, problem, scales, "scale", &record);
  if (best) {
    std::vector<std::pair<double, double>> phis;
    if (choose_on_short) phis.emplace_back(best->scale, 0.0);
    if (options_.fitting_angle_deg <= 0.0) {
      for (double offset : options_.start_phi_offsets_deg) phis.emplace_back(best->scale, offset);
    }
    if (!phis.empty()) {
      std::optional<StartedAdjustment> turned =
          BestStart(odometry, span, poses, problem, phis, "phi", &record);
      // The chained phi's own score is comparable only on the same T: when the scale was chosen
      // on the shorter one, the phi stage's own unturned start stands for it.
      if (choose_on_short || (turned && turned->score < best->score)) best = std::move(turned);
    }
  }
  if (!best || best->problem.points.size() < 20) {
    record.rejection = "too few points";
    return record;
  }
  problem = std::move(best->problem);
  record.start_scale = best->scale;
  record.start_phi_offset_deg = best->phi_offset_deg;
  const std::vector<double>& offsets = options_.start_phi_offsets_deg;
  record.phi_start_at_range_end =
      options_.fitting_angle_deg <= 0.0 && best->phi_offset_deg != 0.0 && !offsets.empty() &&
      (best->phi_offset_deg == *std::min_element(offsets.begin(), offsets.end()) ||
       best->phi_offset_deg == *std::max_element(offsets.begin(), offsets.end()));
  record.triangulated_points = static_cast<int>(problem.points.size());
  record.summary = best->summary;
  if (!record.summary.usable) {
    record.rejection = "not converged";
  } else if (record.summary.final_rms_px >= options_.max_rms_px) {
    record.rejection = "image rms";
  } else if (record.summary.cylinder_rms_m >= options_.max_cylinder_rms * radius) {
    record.rejection = "cylinder rms";
  } else if (problem.model[kPhi] < options_.min_turn_deg * kDeg ||
             M_PI - problem.model[kPhi] < options_.min_turn_deg * kDeg) {
    record.rejection = "no turn";
  } else if ((BlueCamFromWorld(problem).inverse().translation() - Centre(poses[blue])).norm() >
             options_.max_blue_shift * (Centre(poses[blue]) - Centre(poses[red])).norm()) {
    record.rejection = "moved too far";
  }
  if (!record.rejection.empty()) return record;
  record.phi_given = options_.fitting_angle_deg > 0.0;

  const Eigen::Isometry3d blue_before = poses[blue];
  for (int k = red + 1; k < blue; ++k) poses[k] = problem.poses[k - red].ToIsometry().inverse();
  const Eigen::Isometry3d blue_after = BlueCamFromWorld(problem).inverse();
  record.correction = blue_after * blue_before.inverse();
  for (std::size_t k = blue; k < poses.size(); ++k) poses[k] = record.correction * poses[k];
  record.blue_shift_m = (Centre(blue_after) - Centre(blue_before)).norm();
  record.blue_turn_deg = Eigen::AngleAxisd(record.correction.linear()).angle() / kDeg;
  place(problem.model);
  const std::vector<int> inliers = InlierCounts(problem.observations, problem.points.size());
  for (std::size_t p = 0; p < problem.points.size(); ++p) {
    if (inliers[p] < 2) continue;
    record.points.push_back(problem.points[p]);
    record.point_tracks.push_back(best->point_tracks[p]);
  }
  return record;
}

}  // namespace pipescope
