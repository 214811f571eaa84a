#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <utility>
#include <vector>

#include "pipescope/camera/camera.h"
#include "pipescope/estimation/axial_step.h"
#include "pipescope/estimation/global_scale.h"
#include "pipescope/estimation/initial_position.h"
#include "pipescope/estimation/pose_refinement.h"
#include "pipescope/estimation/surface_point.h"
#include "pipescope/estimation/track_statistics.h"
#include "pipescope/estimation/window_adjustment.h"
#include "pipescope/feature/sparse_features.h"
#include "pipescope/io/trajectory.h"
#include "pipescope/util/stage_times.h"

namespace pipescope {

// The window adjustment with the cross-section anchor on (beyond 000, which holds C_X, C_Y
// constant after §5.3.2): every free key frame's place across the pipe is held to the measured
// start with sigma 1 mm, i.e. the crawler is taken to be centred over metres of travel. Where the
// lens sees too little of the wall's curvature (steel-16in) the wall distance, and with it the
// scale, otherwise wanders and keeps any error of the measured start (docs/sparse_vo.md,
// "Holding the wall distance").
WindowAdjustmentOptions SparseVoWindowOptions();

struct SparseOdometerOptions {
  AxialStepOptions axial_step;  // §5.3.1
  int initial_key_frames = 10;  // §5.3.2: N_XY
  InitialPositionOptions initial_position;
  bool optimise_initial_position = true;
  int refine_every = 50;  // §5.3.3: N; the last 2N key frames are refined
  int refine_passes = 2;
  bool refine = true;
  PoseRefinementOptions refinement;
  // Refine the whole window again after the last key frame (beyond 000, which refines only at
  // multiples of N).
  bool refine_at_end = true;
  // Beyond 000: joint six-degree-of-freedom adjustment of the last `window_size` key frames
  // (the oldest `window_fixed` held) every `window_every` key frames, by reprojection through the
  // cylinder; the first adjustment covers the first initial_key_frames, none held.
  bool window_adjustment = true;
  int window_size = 20;
  int window_every = 10;
  int window_fixed = 3;
  WindowAdjustmentOptions window = SparseVoWindowOptions();
  // Beyond 000: after the last key frame, one common cross-section offset and travel scale for
  // all key frames by reprojection over the whole run (estimation/global_scale.h).
  bool global_scale = false;
  GlobalScaleOptions global;
  // Beyond 000: a new key frame where an older one, outside the window, saw the same wall (the
  // way back of an out-and-back run) is matched to it; the old key frame then joins, held, every
  // window adjustment that holds the new one, so the way back is tied to the map of the way out
  // instead of integrating its own drift of the wall distance (docs/sparse_vo.md).
  bool revisit = true;
  // The old key frame nearest along the pipe is tried when it is within this fraction of the
  // start view's extent on the wall (its longer image side at the start's wall distance).
  double revisit_max_offset_fraction = 0.25;
  int revisit_min_inliers = 30;
};

struct SparseKeyFrameRecord {
  std::size_t frame_index = 0;
  int keypoints = 0;
  int tracked = 0;  // keypoints continuing a track of an earlier key frame
};

// What the back end did, for run.json.
struct SparseOdometerSummary {
  std::vector<SparseKeyFrameRecord> key_frame_records;
  Eigen::Vector2d initial_c_xy = Eigen::Vector2d::Zero();
  Eigen::Vector2d optimised_c_xy = Eigen::Vector2d::Zero();
  double initial_reprojection_rms_px = 0.0;
  double optimised_reprojection_rms_px = 0.0;
  int refinements = 0;
  int window_adjustments = 0;
  int revisits = 0;  // key frames matched to an older key frame of the same place (revisit)
  int restarts = 0;  // RestartAt after lost tracks
  GlobalScaleResult global_scale;
};

// A localised frame: its anchor key frame's pose moved by delta_h along the axis, and what it
// saw of the anchor's tracks (to estimate delta_h again once the poses are final).
struct SparseLocalisedFrame {
  std::size_t record = 0;  // the caller's index of the frame
  double timestamp = 0.0;
  std::size_t anchor = 0;
  double delta_h = 0.0;
  std::vector<std::pair<long long, Eigen::Vector3d>> sightings;  // track, bearing
};

struct SparseOdometerOutput {
  Trajectory trajectory;  // every localised frame, world_from_cam, pipe frame (axis Z)
  Trajectory key_frames;
  std::vector<Eigen::Vector3d> points;  // one per track seen in >= 2 key frames (pipe frame)
};

// The sparse back end of 000 §5.3 on a cylinder of known radius, key frame by key frame: the
// tracks' wall points and their statistics S(g) (eq. 35-39), each frame's 1-DOF step along the
// axis (§5.3.1), the initial position (§5.3.2), the 6-DOF refinement (§5.3.3) and, beyond 000,
// the joint window adjustment through the cylinder, revisits of the same wall and a global
// scale. The front end (SparseFeatures) extracts and matches; the pipeline decides which frame
// becomes a key frame.
class SparseOdometer {
 public:
  // `start`: the first key frame's pose in the pipe frame (axis Z, radius `radius_m`);
  // `features` matches revisits; `stage_times` (may be null) gets the back end's stages.
  SparseOdometer(const Camera& camera, double radius_m, const Eigen::Isometry3d& start,
                 const SparseOdometerOptions& options, const SparseFeatures& features,
                 StageTimes* stage_times);

  bool Empty() const { return key_frames_.empty(); }
  // The current key frame's features and index.
  const FrameFeatures& CurrentFeatures() const { return key_frames_.back().features; }
  std::size_t CurrentIndex() const { return key_frames_.size() - 1; }

  // The first key frame, at the start pose.
  void StartAt(std::size_t frame_index, double timestamp, FrameFeatures features);
  // 000 §5.3.1: delta_h of `frame` from the current key frame through the tracks it continues;
  // `sightings` receives what it saw of them.
  double AxialStep(const FrameFeatures& frame, const PairMatches& matches,
                   std::vector<std::pair<long long, Eigen::Vector3d>>* sightings) const;
  // Makes `frame` (matched to the current key frame by `matches`, delta_h from it) the next key
  // frame: it continues the tracks it matched and starts new ones (the global index g), and its
  // wall points enter S(g). Runs 000's batch steps when their key frame count is reached.
  void Promote(std::size_t frame_index, double timestamp, FrameFeatures features,
               const PairMatches& matches, double delta_h);
  // After the tracks were lost (a stretch of wall with too little texture): a new key frame at
  // `predicted`, with new tracks only, from which the chain continues. It is held in every
  // window adjustment and refinement, as the start is.
  void RestartAt(std::size_t frame_index, double timestamp, FrameFeatures features,
                 const Eigen::Isometry3d& predicted);
  // The pose of a localised frame, from its anchor key frame's current pose.
  Eigen::Isometry3d PoseOf(const SparseLocalisedFrame& frame) const;
  // The last adjustments, then every frame's step again against the final poses and statistics.
  SparseOdometerOutput Finish(std::vector<SparseLocalisedFrame>* frames);

  const SparseOdometerSummary& summary() const { return summary_; }

 private:
  struct KeyFrame {
    std::size_t frame_index = 0;
    double timestamp = 0.0;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    FrameFeatures features;
    // A restart's key frame (RestartAt): its pose was predicted, and window adjustments hold it
    // as they hold the start, since no track ties it to the key frames before it.
    bool held = false;
    std::vector<long long> tracks;  // global index g of every keypoint
    // The SIFT descriptors as bytes (OpenCV's SIFT values are whole numbers up to 255), kept
    // for matching when the place is seen again (SparseOdometerOptions::revisit).
    cv::Mat revisit_descriptors;
    // This key frame's entries in S(g), kept so they can be taken out again (§5.3.3).
    std::vector<std::optional<SurfacePoint>> contributions;
  };
  // Key frame `old_key` (outside the window) saw the wall `new_key` sees: `pairs` map old
  // keypoints to new ones (RANSAC inliers).
  struct Revisit {
    std::size_t old_key = 0;
    std::size_t new_key = 0;
    std::vector<IndexMatch> pairs;
  };

  const KeyFrame& Current() const { return key_frames_.back(); }
  double AxialStepFromSightings(
      const Eigen::Isometry3d& anchor,
      const std::vector<std::pair<long long, Eigen::Vector3d>>& sightings) const;
  void OptimiseStart();
  void RefineWindow();
  void CorrectScale();
  void AdjustKeyFrames(std::size_t begin, int fixed);
  void KeepForRevisit(KeyFrame* key) const;
  void FindRevisit();
  std::vector<WindowKeyFrame> RevisitedKeyFrames(std::size_t begin) const;
  std::vector<KeyFrameKeypoint> TrackedKeypoints(const KeyFrame& key) const;
  long long NewTrack();
  void AddContributions(KeyFrame* key);
  void RemoveContributions(KeyFrame* key);

  const Camera& camera_;
  double radius_m_;
  Eigen::Isometry3d start_;
  SparseOdometerOptions options_;
  const SparseFeatures& features_;
  StageTimes* stage_times_;
  double phi_reference_rad_ = 0.0;
  std::vector<KeyFrame> key_frames_;
  std::vector<TrackStatistics> statistics_;  // S(g), indexed by g
  double revisit_max_offset_m_ = 0.0;
  std::vector<Revisit> revisits_;
  SparseOdometerSummary summary_;
};

}  // namespace pipescope
