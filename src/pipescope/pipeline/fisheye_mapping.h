#pragma once

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "pipescope/camera/camera.h"
#include "pipescope/estimation/keyframe_odometry.h"
#include "pipescope/feature/feature_tracker.h"
#include "pipescope/image/pipe_view_classification.h"
#include "pipescope/io/dataset.h"
#include "pipescope/io/trajectory.h"
#include "pipescope/pipeline/dense_map_pass.h"
#include "pipescope/pipeline/loop_closure_pass.h"
#include "pipescope/pipeline/t_intersection_pass.h"
#include "pipescope/util/stage_times.h"

namespace pipescope {

// Fisheye pipe mapping (001 §III A-D): feature tracking with key frames, straight /
// T-intersection classification of the key frames, and visual odometry with the sliding-window
// bundle adjustment and a local straight cylinder in the straight sections. T-intersection key
// frames are chained by the same relative-pose and scale steps and adjusted in windows without
// the cylinder term; then the two-cylinder T model (001 §III-D, TIntersectionPass) adjusts each
// T between two straight sections and joins them.
struct FisheyeMappingOptions {
  FeatureTrackerOptions tracking;
  PipeViewClassificationOptions classification;
  int min_cluster_size = 10;         // key frames; temporal filtering of the classes (001 Fig. 3d)
  KeyframeOdometryOptions odometry;  // odometry.window.radius_m comes from the dataset
  TIntersectionPassOptions t_intersections;  // radius, tau, Huber, MAD: odometry.window's
  LoopClosurePassOptions loop_closure;       // 001 §III-E, after the Ts
  DenseMapPassOptions dense_map;             // 001 §IV-B, after the poses are final
  // After this many unusable frames in a row, tracking starts over from the next frame.
  int max_failures_in_row = 5;
  // A run is unreliable when more than this share of its straight windows was rejected
  // (pipeline/window_confirmation.h).
  double max_rejected_window_share = 0.5;
  // ... or more than this share of one straight section's windows (one with 4 or more).
  double max_rejected_section_window_share = 0.25;
  // The odometry runs on a second thread while the frames are tracked (false: it starts after
  // the last frame, as before; the same key frames in the same order, so the same poses).
  bool overlap_odometry = true;
};

struct FisheyeKeyframe {
  int frame_index = 0;
  double timestamp = 0.0;
  std::string name;
  PipeViewClass initial_class = PipeViewClass::kStraight;
  PipeViewClass filtered_class = PipeViewClass::kStraight;
  double moment_ratio = 0.0;
  int features = 0;
  int matches_cosine = 0;
  int matches_guided = 0;
  int points_used = 0;              // triangulated points seen that fixed the relative scale
  bool direction_rejected = false;  // translation off the recent direction: motion continued
  bool stationary = false;          // no parallax: the camera stood still
  double median_flow_px = 0.0;
  int section = 0;
  Eigen::Isometry3d world_from_cam = Eigen::Isometry3d::Identity();
};

// A run of key frames with one filtered class.
struct FisheyeSection {
  int first_keyframe = 0;
  int last_keyframe = 0;
  PipeViewClass view_class = PipeViewClass::kStraight;
};

struct FisheyeFrameFailure {
  int index = 0;
  std::string name;
  std::string reason;
};

struct FisheyeMappingResult {
  Trajectory trajectory;           // every frame (non-key frames interpolated between key frames)
  Trajectory keyframe_trajectory;  // key frames
  // The key frames as the T pass left them, before the loop closure moved them (empty when no
  // closure was applied): what the closure changed, e.g. each corner's turn, against the truth.
  Trajectory keyframe_trajectory_before_loop_closure;
  std::vector<FisheyeKeyframe> keyframes;
  std::vector<FisheyeSection> sections;
  std::vector<OdometryWindowRecord> windows;
  std::vector<TIntersectionRecord> t_intersections;
  LoopClosureRecord loop_closure;
  std::vector<DenseMapPiece> dense_map;
  std::vector<SparsePoint> points;
  std::vector<FisheyeFrameFailure> failed_frames;
  std::vector<std::string> unreadable_frames;
  int frames = 0;
  int tracking_resets = 0;
  // Where the time went: "tracking" and "classification" (wall seconds, and CPU seconds of the
  // whole process over them: the image read-ahead, OpenCV's workers and the odometry's thread,
  // which runs meanwhile; load on a shared machine changes these less than the wall seconds, but
  // not nothing: up to 20 % between runs of one binary on the first 340 straight frames);
  // "odometry" (wall seconds the odometry's thread worked and its own CPU seconds, not those of
  // Ceres's extra workers); "odometry_wait" (wall seconds the run waited for it after the last
  // frame).
  StageTimes stage_times;
};

// `dense_sink` receives each piece of the dense map as it is finished (BuildDenseMap); without
// one, result.dense_map keeps every piece's map.
FisheyeMappingResult RunFisheyeMapping(const DatasetManifest& manifest, const Camera& camera,
                                       const FisheyeMappingOptions& options,
                                       const DenseMapPieceSink& dense_sink = {});

}  // namespace pipescope
