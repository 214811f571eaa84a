#include "pipescope/pipeline/sparse_vo.h"

#include <algorithm>
#include <cmath>
#include <future>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <set>

#include "pipescope/estimation/surface_point.h"
#include "pipescope/estimation/track_statistics.h"
#include "pipescope/image/gain_mask.h"
#include "pipescope/image/undistortion.h"
#include "pipescope/io/image_source.h"
#include "pipescope/mapping/unrolled_mosaic_pass.h"
#include "pipescope/util/error.h"
#include "pipescope/util/progress.h"
#include "pipescope/util/timer.h"

namespace pipescope {
namespace {

Eigen::Isometry3d MovedAlongAxis(const Eigen::Isometry3d& pose, double delta_h) {
  Eigen::Isometry3d moved = pose;
  moved.translation().z() += delta_h;
  return moved;
}

// Wall and CPU time of one stage, for run.json's timings (StageTimes::Add).
struct StageClock {
  Timer wall;
  ThreadCpuTimer cpu;
};

// The per-stage totals: wall seconds and CPU seconds of the thread that ran each stage.
struct StageTimes {
  std::map<std::string, double>* wall;
  std::map<std::string, double>* cpu;
  void Add(const std::string& stage, double wall_seconds, double cpu_seconds) const {
    (*wall)[stage] += wall_seconds;
    (*cpu)[stage] += cpu_seconds;
  }
  void Add(const std::string& stage, const StageClock& clock) const {
    Add(stage, clock.wall.ElapsedSeconds(), clock.cpu.ElapsedSeconds());
  }
};

// Keypoints of one frame (000 §5.1): positions in the distorted image, SIFT descriptors, bearings.
struct FrameFeatures {
  std::vector<Keypoint> keypoints;
  cv::Mat descriptors;
  std::vector<Eigen::Vector3d> bearings;
  std::vector<bool> has_bearing;
};

struct PairMatches {
  std::vector<IndexMatch> inliers;  // key frame keypoint -> frame keypoint
  int matched = 0;
  double median_flow_px = 0.0;
};

struct KeyFrame {
  std::size_t frame_index = 0;
  double timestamp = 0.0;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  FrameFeatures features;
  std::vector<long long> tracks;  // global index g of every keypoint
  // The SIFT descriptors as bytes (OpenCV's SIFT values are whole numbers up to 255), kept for
  // matching when the place is seen again (SparseVoOptions::revisit).
  cv::Mat revisit_descriptors;
  // This key frame's entries in S(g), kept so they can be taken out again (§5.3.3).
  std::vector<std::optional<SurfacePoint>> contributions;
};

// Key frame `old_key` (outside the window) saw the wall `new_key` sees: `pairs` map old keypoints
// to new ones (RANSAC inliers).
struct Revisit {
  std::size_t old_key = 0;
  std::size_t new_key = 0;
  std::vector<IndexMatch> pairs;
};

// A localised frame: its anchor key frame's pose moved by delta_h along the axis, and what it
// saw of the anchor's tracks (to estimate delta_h again once the poses are final).
struct LocalisedFrame {
  std::size_t record = 0;  // index into SparseVoResult::frames
  double timestamp = 0.0;
  std::size_t anchor = 0;
  double delta_h = 0.0;
  std::vector<std::pair<long long, Eigen::Vector3d>> sightings;  // track, bearing
};

class SparseOdometer {
 public:
  SparseOdometer(const Camera& camera, double radius_m, const Eigen::Isometry3d& start,
                 const SparseVoOptions& options, StageTimes stage_times)
      : camera_(camera),
        radius_m_(radius_m),
        start_(start),
        options_(options),
        stage_times_(stage_times) {
    options_.ransac.focal_length_px = CentralFocalLengthPx(camera);
    const std::optional<Eigen::Vector3d> facing =
        WallPointOfBearing(start, Eigen::Vector3d::UnitZ(), radius_m);
    phi_reference_rad_ = facing ? std::atan2(facing->y(), facing->x()) : M_PI / 2.0;
    // The start view's extent on the wall (its longer image side at the start's wall distance).
    const double wall_distance_m = facing ? (*facing - start.translation()).norm() : radius_m;
    revisit_max_offset_m_ = options.revisit_max_offset_fraction * wall_distance_m *
                            std::max(camera.Width(), camera.Height()) /
                            CentralFocalLengthPx(camera);
  }

  // Thread-safe (runs on the reader thread); `wall` and `cpu` get the Harris and SIFT times.
  FrameFeatures Extract(const cv::Mat& corrected, double wall[2], double cpu[2]) const {
    FrameFeatures features;
    const StageClock harris;
    features.keypoints = DetectRegionHarris(corrected, options_.harris);
    wall[0] = harris.wall.ElapsedSeconds();
    cpu[0] = harris.cpu.ElapsedSeconds();
    const StageClock sift;
    features.descriptors = DescribeWithSift(corrected, features.keypoints, options_.sift);
    wall[1] = sift.wall.ElapsedSeconds();
    cpu[1] = sift.cpu.ElapsedSeconds();
    features.bearings.resize(features.keypoints.size());
    features.has_bearing.resize(features.keypoints.size());
    for (std::size_t i = 0; i < features.keypoints.size(); ++i) {
      const cv::Point2f& p = features.keypoints[i].position;
      features.has_bearing[i] = camera_.Unproject(Eigen::Vector2d(p.x, p.y), &features.bearings[i]);
    }
    return features;
  }

  PairMatches Match(const FrameFeatures& key, const FrameFeatures& frame) const {
    const StageClock matching;
    PairMatches result;
    std::vector<IndexMatch> candidates;
    for (const IndexMatch& match :
         MatchDescriptors(key.descriptors, frame.descriptors, options_.matching)) {
      if (key.has_bearing[match.first] && frame.has_bearing[match.second]) {
        candidates.push_back(match);
      }
    }
    result.matched = static_cast<int>(candidates.size());
    std::vector<Eigen::Vector3d> first, second;
    for (const IndexMatch& match : candidates) {
      first.push_back(key.bearings[match.first]);
      second.push_back(frame.bearings[match.second]);
    }
    stage_times_.Add("matching", matching);
    const StageClock ransac;
    std::vector<bool> inlier;
    FivePointRansacInliers(first, second, options_.ransac, &inlier);
    std::vector<cv::Point2f> from, to;
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      if (!inlier[i]) continue;
      result.inliers.push_back(candidates[i]);
      from.push_back(key.keypoints[candidates[i].first].position);
      to.push_back(frame.keypoints[candidates[i].second].position);
    }
    result.median_flow_px = MedianFlow(from, to);
    stage_times_.Add("ransac", ransac);
    return result;
  }

  bool EndsSpan(const PairMatches& matches) const {
    return EndsKeyFrameSpan(static_cast<int>(matches.inliers.size()), matches.median_flow_px,
                            std::max(camera_.Width(), camera_.Height()), options_.key_frames);
  }

  bool Empty() const { return key_frames_.empty(); }
  const KeyFrame& Current() const { return key_frames_.back(); }
  std::size_t CurrentIndex() const { return key_frames_.size() - 1; }

  void StartAt(std::size_t frame_index, double timestamp, FrameFeatures features) {
    KeyFrame key;
    key.frame_index = frame_index;
    key.timestamp = timestamp;
    key.pose = start_;
    key.features = std::move(features);
    key.tracks.resize(key.features.keypoints.size());
    for (long long& track : key.tracks) track = NewTrack();
    KeepForRevisit(&key);
    AddContributions(&key);
    key_frames_.push_back(std::move(key));
  }

  // 000 §5.3.1: delta_h of `frame` from the current key frame through the tracks it continues.
  double AxialStep(const FrameFeatures& frame, const PairMatches& matches,
                   std::vector<std::pair<long long, Eigen::Vector3d>>* sightings) const {
    const KeyFrame& key = Current();
    sightings->clear();
    for (const IndexMatch& match : matches.inliers) {
      sightings->emplace_back(key.tracks[match.first], frame.bearings[match.second]);
    }
    return AxialStepFromSightings(key.pose, *sightings);
  }

  double AxialStepFromSightings(
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
  void Promote(std::size_t frame_index, double timestamp, FrameFeatures features,
               const PairMatches& matches, double delta_h, SparseVoResult* result) {
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
    // Only the newest key frame is matched again; older descriptors are not needed.
    key_frames_.back().features.descriptors.release();
    key_frames_.push_back(std::move(key));
    result->key_frame_records.push_back(
        {frame_index, static_cast<int>(key_frames_.back().tracks.size()), tracked});

    const std::size_t count = key_frames_.size();
    if (options_.revisit) FindRevisit(result);
    // A measured start replaces §5.3.2's estimate of C_X, C_Y (SparseVoOptions).
    if (options_.optimise_initial_position && !options_.window.hold_first_cross_section &&
        count == static_cast<std::size_t>(options_.initial_key_frames)) {
      OptimiseStart(result);
    }
    if (options_.window_adjustment) {
      if (count == static_cast<std::size_t>(options_.initial_key_frames)) {
        AdjustKeyFrames(0, 0);
        ++result->window_adjustments;
      } else if (count > static_cast<std::size_t>(options_.initial_key_frames) &&
                 count % static_cast<std::size_t>(options_.window_every) == 0) {
        AdjustKeyFrames(count > static_cast<std::size_t>(options_.window_size)
                            ? count - options_.window_size
                            : 0,
                        options_.window_fixed);
        ++result->window_adjustments;
      }
    }
    if (options_.refine && options_.refine_every > 0 &&
        count % static_cast<std::size_t>(options_.refine_every) == 0) {
      RefineWindow();
      ++result->refinements;
    }
  }

  // 000 §5.3.2: C_X, C_Y and the delta_h of the first key frames by reprojection (eq. 45-49).
  void OptimiseStart(SparseVoResult* result) {
    const StageClock clock;
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
    result->initial_c_xy = c_xy;
    result->optimised_c_xy = optimised.c_xy;
    result->initial_reprojection_rms_px = optimised.initial_rms_px;
    result->optimised_reprojection_rms_px = optimised.final_rms_px;
    for (KeyFrame& key : key_frames_) RemoveContributions(&key);
    for (std::size_t a = 0; a < key_frames_.size(); ++a) {
      KeyFrame& key = key_frames_[a];
      key.pose.translation() = Eigen::Vector3d(optimised.c_xy.x(), optimised.c_xy.y(),
                                               first.translation().z() + optimised.delta_h[a]);
    }
    for (KeyFrame& key : key_frames_) AddContributions(&key);
    stage_times_.Add("initial_position", clock);
  }

  // 000 §5.3.3: each of the last 2N key frames in turn, its S(g) entries taken out, refined with
  // six degrees of freedom, and put back; `refine_passes` times.
  void RefineWindow() {
    const StageClock clock;
    const std::size_t count = key_frames_.size();
    const std::size_t window = 2 * static_cast<std::size_t>(options_.refine_every);
    const std::size_t begin = count > window ? count - window : 0;
    for (int pass = 0; pass < options_.refine_passes; ++pass) {
      for (std::size_t k = begin; k < count; ++k) {
        KeyFrame& key = key_frames_[k];
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
    stage_times_.Add("refinement", clock);
  }

  void CorrectScale(SparseVoResult* result) {
    const StageClock clock;
    std::vector<WindowKeyFrame> all;
    for (const KeyFrame& key : key_frames_) {
      WindowKeyFrame entry;
      entry.pose = key.pose;
      entry.keypoints = TrackedKeypoints(key);
      all.push_back(std::move(entry));
    }
    result->global_scale = CorrectGlobalScale(camera_, radius_m_, options_.global, &all);
    for (KeyFrame& key : key_frames_) RemoveContributions(&key);
    for (std::size_t k = 0; k < key_frames_.size(); ++k) key_frames_[k].pose = all[k].pose;
    for (KeyFrame& key : key_frames_) AddContributions(&key);
    stage_times_.Add("global_scale", clock);
  }

  // The window adjustment of key frames [begin, end), the first `fixed` of them held.
  void AdjustKeyFrames(std::size_t begin, int fixed) {
    const std::size_t end = key_frames_.size();
    std::vector<WindowKeyFrame> window = RevisitedKeyFrames(begin);
    const std::size_t revisited = window.size();
    for (std::size_t k = begin; k < end; ++k) {
      const KeyFrame& key = key_frames_[k];
      WindowKeyFrame entry;
      entry.pose = key.pose;
      entry.fixed = static_cast<int>(k - begin) < fixed;
      entry.keypoints = TrackedKeypoints(key);
      window.push_back(std::move(entry));
    }
    const StageClock clock;
    AdjustWindow(camera_, radius_m_, options_.window, &window);
    stage_times_.Add("window_adjustment", clock);
    for (std::size_t k = begin; k < end; ++k) {
      const WindowKeyFrame& adjusted = window[revisited + k - begin];
      if (adjusted.fixed) continue;
      RemoveContributions(&key_frames_[k]);
      key_frames_[k].pose = adjusted.pose;
      AddContributions(&key_frames_[k]);
    }
  }

  void Finish(std::vector<LocalisedFrame>* frames, SparseVoResult* result) {
    const std::size_t count = key_frames_.size();
    if (options_.window_adjustment &&
        count > static_cast<std::size_t>(options_.initial_key_frames) &&
        count % static_cast<std::size_t>(options_.window_every) != 0) {
      AdjustKeyFrames(
          count > static_cast<std::size_t>(options_.window_size) ? count - options_.window_size : 0,
          options_.window_fixed);
      ++result->window_adjustments;
    }
    if (options_.refine && options_.refine_at_end &&
        static_cast<int>(key_frames_.size()) > options_.initial_key_frames &&
        key_frames_.size() % options_.refine_every != 0) {
      RefineWindow();
      ++result->refinements;
    }
    if (options_.global_scale) CorrectScale(result);
    // Every frame again against the final poses and statistics.
    for (LocalisedFrame& frame : *frames) {
      if (frame.sightings.empty()) continue;
      frame.delta_h = AxialStepFromSightings(key_frames_[frame.anchor].pose, frame.sightings);
    }
    for (const LocalisedFrame& frame : *frames) {
      result->trajectory.push_back(ToStampedPose(
          frame.timestamp, MovedAlongAxis(key_frames_[frame.anchor].pose, frame.delta_h)));
    }
    for (const KeyFrame& key : key_frames_) {
      result->key_frames.push_back(ToStampedPose(key.timestamp, key.pose));
    }
    for (const TrackStatistics& statistics : statistics_) {
      if (statistics.n >= 2.0) {
        result->points.push_back(FromSurface(statistics.Mean(), radius_m_, phi_reference_rad_));
      }
    }
  }

 private:
  void KeepForRevisit(KeyFrame* key) const {
    if (options_.revisit) key->features.descriptors.convertTo(key->revisit_descriptors, CV_8U);
  }

  // The newest key frame against the older key frame nearest to it along the pipe, among those
  // no window adjustment holds any more (SparseVoOptions::revisit).
  void FindRevisit(SparseVoResult* result) {
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
    const PairMatches matches = Match(old_features, key_frames_[newest].features);
    if (static_cast<int>(matches.inliers.size()) < options_.revisit_min_inliers) return;
    revisits_.push_back({nearest, newest, matches.inliers});
    ++result->revisits;
  }

  // Held window entries for the old key frames of the revisits whose new key frame is in the
  // window from `begin` on: each old keypoint carries the track of the new keypoint it matched,
  // so every transfer from it ties the window to the old key frame's pose.
  std::vector<WindowKeyFrame> RevisitedKeyFrames(std::size_t begin) const {
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
  std::vector<KeyFrameKeypoint> TrackedKeypoints(const KeyFrame& key) const {
    std::vector<KeyFrameKeypoint> keypoints;
    for (std::size_t i = 0; i < key.tracks.size(); ++i) {
      if (!key.features.has_bearing[i] || statistics_[key.tracks[i]].n < 2.0) continue;
      const cv::Point2f& p = key.features.keypoints[i].position;
      keypoints.push_back({key.tracks[i], Eigen::Vector2d(p.x, p.y), key.features.bearings[i]});
    }
    return keypoints;
  }

  long long NewTrack() {
    statistics_.emplace_back();
    return static_cast<long long>(statistics_.size()) - 1;
  }

  void AddContributions(KeyFrame* key) {
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

  void RemoveContributions(KeyFrame* key) {
    for (std::size_t i = 0; i < key->contributions.size(); ++i) {
      if (key->contributions[i]) statistics_[key->tracks[i]].Remove(*key->contributions[i]);
    }
    key->contributions.assign(key->tracks.size(), std::nullopt);
  }

  const Camera& camera_;
  double radius_m_;
  Eigen::Isometry3d start_;
  SparseVoOptions options_;
  double phi_reference_rad_ = 0.0;
  std::vector<KeyFrame> key_frames_;
  std::vector<TrackStatistics> statistics_;  // S(g), indexed by g
  double revisit_max_offset_m_ = 0.0;
  std::vector<Revisit> revisits_;
  StageTimes stage_times_;
};

// The unrolled appearance map (000 Fig. 15/17) from the frames at their estimated poses.
void BuildMosaic(const DatasetManifest& manifest, const Camera& camera, const cv::Mat& gain_mask,
                 double radius_m, double pixel_m, double spacing_cells, SparseVoResult* result) {
  std::map<std::size_t, Eigen::Isometry3d> poses;
  std::size_t pose_index = 0;
  for (const SparseFrameRecord& record : result->frames) {
    if (!record.failure.empty()) continue;
    poses[record.index] = ToIsometry(result->trajectory[pose_index++]);
  }
  UnrolledMosaicMap map = MosaicAtPoses(manifest, camera, gain_mask, poses, radius_m, pixel_m,
                                        3.0 * radius_m, spacing_cells * pixel_m);
  result->mosaic = std::move(map.image);
  result->mosaic_pixel_m = map.pixel_m;
  result->mosaic_origin_m = map.origin_m;
}

void CheckOptions(const SparseVoOptions& options) {
  auto require = [](bool ok, const std::string& message) {
    if (!ok) throw InputError(message);
  };
  require(options.harris.grid_rows > 0 && options.harris.grid_cols > 0,
          "grid_rows, grid_cols: must be positive");
  require(options.harris.per_cell > 0, "per_cell: must be positive");
  require(options.initial_key_frames >= 2, "initial_key_frames: must be at least 2");
  require(options.refine_every >= 1, "refine_every: must be at least 1");
  require(options.window_every >= 1 && options.window_size > options.window_fixed &&
              options.window_fixed >= 0,
          "window_size, window_every, window_fixed: need window_every >= 1 and window_size > "
          "window_fixed >= 0");
  require(options.min_correspondences >= 6, "min_correspondences: must be at least 6");
  require(options.wall_distance_m >= 0.0, "wall_distance_m: must not be negative");
  require(options.mosaic_pixel_m >= 0.0, "mosaic_pixel_m: must not be negative");
}

}  // namespace

RegionHarrisOptions SparseVoRegionHarrisOptions() {
  RegionHarrisOptions options;
  options.sigma_window_px = 2.0;
  return options;
}

WindowAdjustmentOptions SparseVoWindowOptions() {
  WindowAdjustmentOptions options;
  options.cross_section_anchor_sigma_m = 0.001;
  return options;
}

SparseVoResult RunSparseVo(const DatasetManifest& manifest, const Camera& camera,
                           const SparseVoOptions& options) {
  CheckOptions(options);
  const double radius = RequireInnerRadius(manifest);
  double wall_distance = options.wall_distance_m;
  const bool has_reference_scale =
      manifest.reference_scale_px_per_m && *manifest.reference_scale_px_per_m > 0.0;
  const bool start_measured = wall_distance > 0.0 || has_reference_scale;
  if (!(wall_distance > 0.0)) {
    wall_distance = has_reference_scale
                        ? CentralFocalLengthPx(camera) / *manifest.reference_scale_px_per_m
                        : radius;
  }
  SparseVoOptions effective = options;
  effective.window.hold_first_cross_section = options.hold_measured_start && start_measured;
  if (wall_distance >= 2.0 * radius) {
    throw InputError(ManifestName(manifest) + ": the start camera would be " +
                     std::to_string(wall_distance) +
                     " m from the wall, beyond the pipe's diameter (wall_distance_m or "
                     "reference_scale_px_per_m)");
  }
  const Eigen::Isometry3d start = MountedStartPose(options.mount, radius, wall_distance);
  // Without a measured start there is no place to anchor the cross-section to.
  if (!start_measured) effective.window.cross_section_anchor_sigma_m = 0.0;
  effective.window.cross_section_anchor_xy = start.translation().head<2>();
  const cv::Mat gain_mask =
      manifest.gain_mask_path.empty() ? cv::Mat() : ReadGainMask(manifest.gain_mask_path);
  if (!gain_mask.empty() &&
      (gain_mask.cols != camera.Width() || gain_mask.rows != camera.Height())) {
    throw InputError(manifest.gain_mask_path.string() +
                     ": gain mask size differs from the camera's");
  }

  SparseVoResult result;
  const StageTimes stage_times{&result.stage_seconds, &result.stage_cpu_seconds};
  SparseOdometer odometer(camera, radius, start, effective, stage_times);
  std::vector<LocalisedFrame> localised;
  // The newest localised frame since the key frame: the next key frame when the span ends.
  struct Candidate {
    std::size_t frame_index;
    double timestamp;
    FrameFeatures features;
    PairMatches matches;
    double delta_h;
    std::size_t localised;
  };
  std::optional<Candidate> candidate;

  auto source = ImageSource::Open(manifest, {camera.Width(), camera.Height()});
  ProgressBar progress("sparse", source->FrameCount());
  Timer timer;
  const ProcessCpuTimer cpu_timer;
  // Reading, gain correction and feature extraction of the next frame run on a second thread
  // while this one matches and estimates (options.pipelined), one frame ahead.
  struct Loaded {
    Frame frame;
    double saturated = 0.0;
    FrameFeatures features;
    double wall[3] = {0.0, 0.0, 0.0};  // reading, Harris, SIFT
    double cpu[3] = {0.0, 0.0, 0.0};
  };
  auto load = [&]() -> std::optional<Loaded> {
    const StageClock read;
    std::optional<Frame> frame = source->Next();
    if (!frame) return std::nullopt;
    Loaded loaded;
    loaded.saturated = SaturatedFraction(frame->grey, options.saturation_level);
    if (loaded.saturated <= options.max_saturated_fraction) {
      const cv::Mat corrected =
          gain_mask.empty() ? frame->grey : ApplyGainMask(frame->grey, gain_mask);
      loaded.wall[0] = read.wall.ElapsedSeconds();
      loaded.cpu[0] = read.cpu.ElapsedSeconds();
      loaded.features = odometer.Extract(corrected, loaded.wall + 1, loaded.cpu + 1);
    }
    loaded.frame = std::move(*frame);
    return loaded;
  };
  const std::launch policy = options.pipelined ? std::launch::async : std::launch::deferred;
  std::future<std::optional<Loaded>> next = std::async(policy, load);
  while (true) {
    std::optional<Loaded> loaded = next.get();
    if (!loaded) break;
    next = std::async(policy, load);
    stage_times.Add("read", loaded->wall[0], loaded->cpu[0]);
    stage_times.Add("features_harris", loaded->wall[1], loaded->cpu[1]);
    stage_times.Add("features_sift", loaded->wall[2], loaded->cpu[2]);
    const Frame* frame = &loaded->frame;
    progress.Update(frame->index + 1);
    SparseFrameRecord record;
    record.index = frame->index;
    record.timestamp = frame->timestamp;
    record.name = frame->name;
    if (loaded->saturated > options.max_saturated_fraction) {
      record.failure = std::to_string(static_cast<int>(std::round(100.0 * loaded->saturated))) +
                       " % of the pixels saturated";
      result.frames.push_back(std::move(record));
      continue;
    }
    FrameFeatures features = std::move(loaded->features);
    record.keypoints = static_cast<int>(features.keypoints.size());
    if (odometer.Empty()) {
      if (static_cast<int>(features.keypoints.size()) < options.min_correspondences) {
        record.failure = "too few keypoints to start";
        result.frames.push_back(std::move(record));
        continue;
      }
      odometer.StartAt(frame->index, frame->timestamp, std::move(features));
      record.key_frame = true;
      result.key_frame_records.push_back({frame->index, record.keypoints, 0});
      localised.push_back({result.frames.size(), frame->timestamp, 0, 0.0, {}});
      result.frames.push_back(std::move(record));
      continue;
    }
    PairMatches matches = odometer.Match(odometer.Current().features, features);
    if (odometer.EndsSpan(matches) && candidate) {
      // 000 §5.1: the frame before the one that ends the span becomes the key frame.
      odometer.Promote(candidate->frame_index, candidate->timestamp, std::move(candidate->features),
                       candidate->matches, candidate->delta_h, &result);
      LocalisedFrame& promoted = localised[candidate->localised];
      promoted.anchor = odometer.CurrentIndex();
      promoted.delta_h = 0.0;
      promoted.sightings.clear();
      result.frames[promoted.record].key_frame = true;
      candidate.reset();
      matches = odometer.Match(odometer.Current().features, features);
    }
    record.matches = matches.matched;
    record.inliers = static_cast<int>(matches.inliers.size());
    if (record.inliers < options.min_correspondences) {
      record.failure =
          "only " + std::to_string(record.inliers) + " inlier correspondences to the key frame";
      result.frames.push_back(std::move(record));
      continue;
    }
    LocalisedFrame frame_pose;
    frame_pose.record = result.frames.size();
    frame_pose.timestamp = frame->timestamp;
    frame_pose.anchor = odometer.CurrentIndex();
    frame_pose.delta_h = odometer.AxialStep(features, matches, &frame_pose.sightings);
    if (odometer.EndsSpan(matches)) {
      // Already too far from the key frame it follows: it becomes a key frame itself.
      odometer.Promote(frame->index, frame->timestamp, std::move(features), matches,
                       frame_pose.delta_h, &result);
      frame_pose.anchor = odometer.CurrentIndex();
      frame_pose.delta_h = 0.0;
      frame_pose.sightings.clear();
      record.key_frame = true;
    } else {
      candidate = Candidate{frame->index,       frame->timestamp,   std::move(features),
                            std::move(matches), frame_pose.delta_h, localised.size()};
    }
    localised.push_back(std::move(frame_pose));
    result.frames.push_back(std::move(record));
  }
  progress.Finish();
  result.skipped_frames = source->skipped_frames();
  if (odometer.Empty()) {
    throw InputError(ManifestName(manifest) +
                     ": no usable frames (none readable with enough "
                     "keypoints)");
  }
  odometer.Finish(&localised, &result);
  result.odometry_seconds = timer.ElapsedSeconds();
  result.odometry_cpu_seconds = cpu_timer.ElapsedSeconds();
  if (options.build_mosaic) {
    double pixel_m = options.mosaic_pixel_m;
    if (!(pixel_m > 0.0)) pixel_m = wall_distance / CentralFocalLengthPx(camera);
    const Timer mosaic_timer;
    const ProcessCpuTimer mosaic_cpu_timer;
    BuildMosaic(manifest, camera, gain_mask, radius, pixel_m, options.mosaic_spacing_cells,
                &result);
    result.mosaic_seconds = mosaic_timer.ElapsedSeconds();
    result.mosaic_cpu_seconds = mosaic_cpu_timer.ElapsedSeconds();
  }
  return result;
}

}  // namespace pipescope
