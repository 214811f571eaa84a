#include "pipescope/estimation/sparse_odometer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include "pipescope/image/undistortion.h"

namespace pipescope {
namespace {

Eigen::Isometry3d MovedAlongAxis(const Eigen::Isometry3d& pose, double delta_h) {
  Eigen::Isometry3d moved = pose;
  moved.translation().z() += delta_h;
  return moved;
}

}  // namespace

WindowAdjustmentOptions SparseVoWindowOptions() {
  WindowAdjustmentOptions options;
  options.cross_section_anchor_sigma_m = 0.001;
  // The images overrule it where they see the wall's curvature (docs/conditions.md: a crawler
  // wandering 5 % of the radius over 2 m, 6-inch 0.123 % Gaussian against 0.052 % robust).
  options.cross_section_anchor_robust = true;
  return options;
}

SparseOdometer::SparseOdometer(const Camera& camera, double radius_m,
                               const Eigen::Isometry3d& start, const SparseOdometerOptions& options,
                               const SparseFeatures& features, StageTimes* stage_times)
    : camera_(camera),
      radius_m_(radius_m),
      start_(start),
      options_(options),
      features_(features),
      stage_times_(stage_times) {
  const std::optional<Eigen::Vector3d> facing =
      WallPointOfBearing(start, Eigen::Vector3d::UnitZ(), radius_m);
  phi_reference_rad_ = facing ? std::atan2(facing->y(), facing->x()) : M_PI / 2.0;
  // The start view's extent on the wall (its longer image side at the start's wall distance).
  const double wall_distance_m = facing ? (*facing - start.translation()).norm() : radius_m;
  revisit_max_offset_m_ = options.revisit_max_offset_fraction * wall_distance_m *
                          std::max(camera.Width(), camera.Height()) / CentralFocalLengthPx(camera);
}

void SparseOdometer::StartAt(std::size_t frame_index, double timestamp, FrameFeatures features) {
  RestartAt(frame_index, timestamp, std::move(features), start_);
  key_frames_.back().held = false;
}

void SparseOdometer::RestartAt(std::size_t frame_index, double timestamp, FrameFeatures features,
                               const Eigen::Isometry3d& predicted) {
  if (!key_frames_.empty()) {
    key_frames_.back().features.descriptors.release();
    key_frames_.back().features.pyramid.clear();
    ++summary_.restarts;
  }
  KeyFrame key;
  key.frame_index = frame_index;
  key.timestamp = timestamp;
  key.pose = predicted;
  key.held = true;
  key.features = std::move(features);
  key.tracks.resize(key.features.keypoints.size());
  for (long long& track : key.tracks) track = NewTrack();
  KeepForRevisit(&key);
  AddContributions(&key);
  summary_.key_frame_records.push_back({frame_index, static_cast<int>(key.tracks.size()), 0});
  key_frames_.push_back(std::move(key));
}

Eigen::Isometry3d SparseOdometer::PoseOf(const SparseLocalisedFrame& frame) const {
  return MovedAlongAxis(key_frames_[frame.anchor].pose, frame.delta_h);
}

// 000 §5.3.1: delta_h of `frame` from the current key frame through the tracks it continues.
double SparseOdometer::AxialStep(
    const FrameFeatures& frame, const PairMatches& matches,
    std::vector<std::pair<long long, Eigen::Vector3d>>* sightings) const {
  const KeyFrame& key = Current();
  sightings->clear();
  for (const IndexMatch& match : matches.inliers) {
    sightings->emplace_back(key.tracks[match.first], frame.bearings[match.second]);
  }
  return AxialStepFromSightings(key.pose, *sightings);
}

double SparseOdometer::AxialStepFromSightings(
    const Eigen::Isometry3d& anchor,
    const std::vector<std::pair<long long, Eigen::Vector3d>>& sightings) const {
  std::vector<AxialStepObservation> observations;
  for (const auto& [track, bearing] : sightings) {
    const TrackStatistics& statistics = statistics_[track];
    if (!(statistics.n > 0.0)) continue;
    const std::optional<Eigen::Vector3d> wall = WallPointOfBearing(anchor, bearing, radius_m_);
    if (!wall) continue;
    observations.push_back({ToSurface(*wall, radius_m_, phi_reference_rad_), statistics});
  }
  return EstimateAxialStep(observations, options_.axial_step);
}

// Makes `frame` (matched to the current key frame by `matches`, delta_h from it) the next key
// frame: it continues the tracks it matched and starts new ones (the global index g), and its
// wall points enter S(g). Runs 000's batch steps when their key frame count is reached.
void SparseOdometer::Promote(std::size_t frame_index, double timestamp, FrameFeatures features,
                             const PairMatches& matches, double delta_h) {
  KeyFrame key;
  key.frame_index = frame_index;
  key.timestamp = timestamp;
  key.pose = MovedAlongAxis(Current().pose, delta_h);
  key.tracks.assign(features.keypoints.size(), -1);
  int tracked = 0;
  for (const IndexMatch& match : matches.inliers) {
    key.tracks[match.second] = Current().tracks[match.first];
    ++tracked;
  }
  for (long long& track : key.tracks) {
    if (track < 0) track = NewTrack();
  }
  key.features = std::move(features);
  KeepForRevisit(&key);
  AddContributions(&key);
  // Only the newest key frame is matched again; older descriptors and pyramids are not needed.
  key_frames_.back().features.descriptors.release();
  key_frames_.back().features.pyramid.clear();
  key_frames_.push_back(std::move(key));
  summary_.key_frame_records.push_back(
      {frame_index, static_cast<int>(key_frames_.back().tracks.size()), tracked});

  const std::size_t count = key_frames_.size();
  if (options_.revisit) FindRevisit();
  // A measured start replaces §5.3.2's estimate of C_X, C_Y (SparseOdometerOptions).
  if (options_.optimise_initial_position && !options_.window.hold_first_cross_section &&
      summary_.restarts == 0 && count == static_cast<std::size_t>(options_.initial_key_frames)) {
    OptimiseStart();
  }
  if (options_.window_adjustment) {
    if (count == static_cast<std::size_t>(options_.initial_key_frames)) {
      AdjustKeyFrames(0, 0);
      ++summary_.window_adjustments;
    } else if (count > static_cast<std::size_t>(options_.initial_key_frames) &&
               count % static_cast<std::size_t>(options_.window_every) == 0) {
      AdjustKeyFrames(
          count > static_cast<std::size_t>(options_.window_size) ? count - options_.window_size : 0,
          options_.window_fixed);
      ++summary_.window_adjustments;
    }
  }
  if (options_.refine && options_.refine_every > 0 &&
      count % static_cast<std::size_t>(options_.refine_every) == 0) {
    RefineWindow();
    ++summary_.refinements;
  }
}

// 000 §5.3.2: C_X, C_Y and the delta_h of the first key frames by reprojection (eq. 45-49).
void SparseOdometer::OptimiseStart() {
  const StageClock<> clock;
  std::vector<std::vector<KeyFrameKeypoint>> keypoints(key_frames_.size());
  std::vector<double> delta_h(key_frames_.size());
  const Eigen::Isometry3d& first = key_frames_.front().pose;
  for (std::size_t a = 0; a < key_frames_.size(); ++a) {
    const KeyFrame& key = key_frames_[a];
    delta_h[a] = key.pose.translation().z() - first.translation().z();
    keypoints[a] = TrackedKeypoints(key);
  }
  const Eigen::Vector2d c_xy = first.translation().head<2>();
  const InitialPositionResult optimised = OptimiseInitialPosition(
      camera_, first.linear(), radius_m_, c_xy, delta_h, keypoints, options_.initial_position);
  summary_.initial_c_xy = c_xy;
  summary_.optimised_c_xy = optimised.c_xy;
  summary_.initial_reprojection_rms_px = optimised.initial_rms_px;
  summary_.optimised_reprojection_rms_px = optimised.final_rms_px;
  for (KeyFrame& key : key_frames_) RemoveContributions(&key);
  for (std::size_t a = 0; a < key_frames_.size(); ++a) {
    KeyFrame& key = key_frames_[a];
    key.pose.translation() = Eigen::Vector3d(optimised.c_xy.x(), optimised.c_xy.y(),
                                             first.translation().z() + optimised.delta_h[a]);
  }
  for (KeyFrame& key : key_frames_) AddContributions(&key);
  clock.AddTo(stage_times_, "initial_position");
}

// 000 §5.3.3: each of the last 2N key frames in turn, its S(g) entries taken out, refined with
// six degrees of freedom, and put back; `refine_passes` times.
void SparseOdometer::RefineWindow() {
  const StageClock<> clock;
  const std::size_t count = key_frames_.size();
  const std::size_t window = 2 * static_cast<std::size_t>(options_.refine_every);
  const std::size_t begin = count > window ? count - window : 0;
  for (int pass = 0; pass < options_.refine_passes; ++pass) {
    for (std::size_t k = begin; k < count; ++k) {
      KeyFrame& key = key_frames_[k];
      if (key.held) continue;
      RemoveContributions(&key);
      std::vector<SurfaceObservation> observations;
      for (std::size_t i = 0; i < key.tracks.size(); ++i) {
        if (!key.features.has_bearing[i]) continue;
        const TrackStatistics& statistics = statistics_[key.tracks[i]];
        if (!(statistics.n > 0.0)) continue;
        observations.push_back({key.features.bearings[i], statistics});
      }
      key.pose = RefinePoseOnSurface(key.pose, observations, radius_m_, phi_reference_rad_,
                                     options_.refinement);
      AddContributions(&key);
    }
  }
  clock.AddTo(stage_times_, "refinement");
}

void SparseOdometer::CorrectScale() {
  const StageClock<> clock;
  std::vector<WindowKeyFrame> all;
  for (const KeyFrame& key : key_frames_) {
    WindowKeyFrame entry;
    entry.pose = key.pose;
    entry.keypoints = TrackedKeypoints(key);
    all.push_back(std::move(entry));
  }
  summary_.global_scale = CorrectGlobalScale(camera_, radius_m_, options_.global, &all);
  for (KeyFrame& key : key_frames_) RemoveContributions(&key);
  for (std::size_t k = 0; k < key_frames_.size(); ++k) key_frames_[k].pose = all[k].pose;
  for (KeyFrame& key : key_frames_) AddContributions(&key);
  clock.AddTo(stage_times_, "global_scale");
}

// The window adjustment of key frames [begin, end), the first `fixed` of them held.
void SparseOdometer::AdjustKeyFrames(std::size_t begin, int fixed) {
  const std::size_t end = key_frames_.size();
  std::vector<WindowKeyFrame> window = RevisitedKeyFrames(begin);
  const std::size_t revisited = window.size();
  // A window that holds a restart's key frame holds the start too: the gauge prior on the first
  // key frame applies only when none is held.
  bool holds_restart = false;
  for (std::size_t k = begin; k < end; ++k) holds_restart = holds_restart || key_frames_[k].held;
  for (std::size_t k = begin; k < end; ++k) {
    const KeyFrame& key = key_frames_[k];
    WindowKeyFrame entry;
    entry.pose = key.pose;
    entry.fixed = static_cast<int>(k - begin) < fixed || key.held || (holds_restart && k == 0);
    entry.keypoints = TrackedKeypoints(key);
    window.push_back(std::move(entry));
  }
  const StageClock<> clock;
  AdjustWindow(camera_, radius_m_, options_.window, &window);
  clock.AddTo(stage_times_, "window_adjustment");
  for (std::size_t k = begin; k < end; ++k) {
    const WindowKeyFrame& adjusted = window[revisited + k - begin];
    if (adjusted.fixed) continue;
    RemoveContributions(&key_frames_[k]);
    key_frames_[k].pose = adjusted.pose;
    AddContributions(&key_frames_[k]);
  }
}

SparseOdometerOutput SparseOdometer::Finish(std::vector<SparseLocalisedFrame>* frames) {
  SparseOdometerOutput output;
  const std::size_t count = key_frames_.size();
  if (options_.window_adjustment && count > static_cast<std::size_t>(options_.initial_key_frames) &&
      count % static_cast<std::size_t>(options_.window_every) != 0) {
    AdjustKeyFrames(
        count > static_cast<std::size_t>(options_.window_size) ? count - options_.window_size : 0,
        options_.window_fixed);
    ++summary_.window_adjustments;
  }
  if (options_.refine && options_.refine_at_end &&
      static_cast<int>(key_frames_.size()) > options_.initial_key_frames &&
      key_frames_.size() % options_.refine_every != 0) {
    RefineWindow();
    ++summary_.refinements;
  }
  if (options_.global_scale) CorrectScale();
  // Every frame again against the final poses and statistics.
  for (SparseLocalisedFrame& frame : *frames) {
    if (frame.sightings.empty()) continue;
    frame.delta_h = AxialStepFromSightings(key_frames_[frame.anchor].pose, frame.sightings);
  }
  for (const SparseLocalisedFrame& frame : *frames) {
    output.trajectory.push_back(ToStampedPose(
        frame.timestamp, MovedAlongAxis(key_frames_[frame.anchor].pose, frame.delta_h)));
  }
  for (const KeyFrame& key : key_frames_) {
    output.key_frames.push_back(ToStampedPose(key.timestamp, key.pose));
  }
  for (const TrackStatistics& statistics : statistics_) {
    if (statistics.n >= 2.0) {
      output.points.push_back(FromSurface(statistics.Mean(), radius_m_, phi_reference_rad_));
    }
  }
  return output;
}

void SparseOdometer::KeepForRevisit(KeyFrame* key) const {
  if (options_.revisit) key->features.descriptors.convertTo(key->revisit_descriptors, CV_8U);
}

// The newest key frame against the older key frame nearest to it along the pipe, among those
// no window adjustment holds any more (SparseOdometerOptions::revisit).
void SparseOdometer::FindRevisit() {
  const std::size_t newest = key_frames_.size() - 1;
  const std::size_t window = static_cast<std::size_t>(options_.window_size);
  if (newest < window) return;
  const double h = key_frames_[newest].pose.translation().z();
  std::size_t nearest = 0;
  double offset = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k + window < newest; ++k) {
    const double d = std::abs(key_frames_[k].pose.translation().z() - h);
    if (d < offset) {
      offset = d;
      nearest = k;
    }
  }
  if (!(offset <= revisit_max_offset_m_)) return;
  FrameFeatures old_features = key_frames_[nearest].features;
  key_frames_[nearest].revisit_descriptors.convertTo(old_features.descriptors, CV_32F);
  const PairMatches matches =
      features_.Match(old_features, key_frames_[newest].features, stage_times_);
  if (static_cast<int>(matches.inliers.size()) < options_.revisit_min_inliers) return;
  revisits_.push_back({nearest, newest, matches.inliers});
  ++summary_.revisits;
}

// Held window entries for the old key frames of the revisits whose new key frame is in the
// window from `begin` on: each old keypoint carries the track of the new keypoint it matched,
// so every transfer from it ties the window to the old key frame's pose.
std::vector<WindowKeyFrame> SparseOdometer::RevisitedKeyFrames(std::size_t begin) const {
  std::map<std::size_t, WindowKeyFrame> entries;
  std::map<std::size_t, std::set<long long>> tracks_of;
  for (const Revisit& revisit : revisits_) {
    if (revisit.new_key < begin) continue;
    const KeyFrame& old_key = key_frames_[revisit.old_key];
    const KeyFrame& new_key = key_frames_[revisit.new_key];
    WindowKeyFrame& entry = entries[revisit.old_key];
    entry.pose = old_key.pose;
    entry.fixed = true;
    for (const IndexMatch& pair : revisit.pairs) {
      const long long track = new_key.tracks[pair.second];
      // Only tracks the window adjusts (seen in two or more key frames: TrackedKeypoints).
      if (statistics_[track].n < 2.0 || !tracks_of[revisit.old_key].insert(track).second) {
        continue;
      }
      const cv::Point2f& p = old_key.features.keypoints[pair.first].position;
      entry.keypoints.push_back(
          {track, Eigen::Vector2d(p.x, p.y), old_key.features.bearings[pair.first]});
    }
  }
  std::vector<WindowKeyFrame> window;
  for (auto& [index, entry] : entries) window.push_back(std::move(entry));
  return window;
}

// The key frame's keypoints on tracks seen in two or more key frames.
std::vector<KeyFrameKeypoint> SparseOdometer::TrackedKeypoints(const KeyFrame& key) const {
  std::vector<KeyFrameKeypoint> keypoints;
  for (std::size_t i = 0; i < key.tracks.size(); ++i) {
    if (!key.features.has_bearing[i] || statistics_[key.tracks[i]].n < 2.0) continue;
    const cv::Point2f& p = key.features.keypoints[i].position;
    keypoints.push_back({key.tracks[i], Eigen::Vector2d(p.x, p.y), key.features.bearings[i]});
  }
  return keypoints;
}

long long SparseOdometer::NewTrack() {
  statistics_.emplace_back();
  return static_cast<long long>(statistics_.size()) - 1;
}

void SparseOdometer::AddContributions(KeyFrame* key) {
  key->contributions.assign(key->tracks.size(), std::nullopt);
  for (std::size_t i = 0; i < key->tracks.size(); ++i) {
    if (!key->features.has_bearing[i]) continue;
    const std::optional<Eigen::Vector3d> wall =
        WallPointOfBearing(key->pose, key->features.bearings[i], radius_m_);
    if (!wall) continue;
    const SurfacePoint point = ToSurface(*wall, radius_m_, phi_reference_rad_);
    statistics_[key->tracks[i]].Add(point);
    key->contributions[i] = point;
  }
}

void SparseOdometer::RemoveContributions(KeyFrame* key) {
  for (std::size_t i = 0; i < key->contributions.size(); ++i) {
    if (key->contributions[i]) statistics_[key->tracks[i]].Remove(*key->contributions[i]);
  }
  key->contributions.assign(key->tracks.size(), std::nullopt);
}

}  // namespace pipescope
