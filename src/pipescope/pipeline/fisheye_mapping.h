#pragma once

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "pipescope/camera/camera.h"
#include "pipescope/fisheye/feature_tracker.h"
#include "pipescope/fisheye/pipe_view_classification.h"
#include "pipescope/fisheye/straight_window_adjustment.h"
#include "pipescope/io/dataset.h"
#include "pipescope/io/trajectory.h"

namespace pipescope {

// Fisheye pipe mapping, part 1 (001 §III A-C): feature tracking with key frames, straight /
// T-intersection classification of the key frames, and visual odometry with the sliding-window
// bundle adjustment and a local straight cylinder in the straight sections. T-intersection key
// frames are chained by the same relative-pose and scale steps and adjusted in windows without
// the cylinder term (the two-cylinder T model of 001 §III-D is part 2).
struct FisheyeMappingOptions {
  FeatureTrackerOptions tracking;
  PipeViewClassificationOptions classification;
  int min_cluster_size = 10;     // key frames; temporal filtering of the classes (001 Fig. 3d)
  StraightWindowOptions window;  // radius_m comes from the dataset
  // 001 runs the SBA every 50 key frames over the last 100. Here the chain of relative poses
  // between windows drifts in scale far more than 001's did (our relative rotations are off by
  // about a degree at 1 cm baselines), so the defaults adjust every 10 key frames over the
  // last 50; 50 / 100 is a --config away (window_interval, window_size). On the first 200
  // frames of the straight benchmark, 50 / 100 gave a 78.5 % distance error, 10 / 50 gave 15 %
  // (docs/fisheye_mapping.md).
  int window_interval = 10;
  int window_size = 50;
  // New points need this angle between their first and latest rays ...
  double min_triangulation_angle_deg = 1.5;
  // ... and a reprojection error below this in both key frames.
  double max_triangulation_error_px = 3.0;
  // A point fixes the relative scale only when its rays in the two key frames part by at least
  // this angle (near-parallel rays give wild depths, and their ratios bias the scale).
  double min_scale_parallax_rad = 0.03;
  // In a straight section each key-frame step length comes from the radius: the two-view
  // points are put on the wall of the current axis (cylinder_scale.h), so the scale does not
  // chain from key frame to key frame. Below this many points, the earlier structure fixes it.
  int min_cylinder_scale_points = 20;
  // Fit the axis together with the scale to each step's two-view points (FitScaleAndAxis), so
  // the step length depends on no earlier estimate; false: the scale alone, on the axis of the
  // last converged window. Off: on the first 340 frames of the straight benchmark the per-step
  // axis held the scale to 2 % for 240 key frames, then halved it after the tracking reset
  // (-19.7 % distance); the window axis gave -5.9 % (docs/fisheye_mapping.md).
  bool fit_axis_per_step = false;
  // ... but when no window has been applied for this many key frames, the window axis is stale
  // (rotation drift) and the axis is fitted per step until a window is applied again.
  int stale_axis_keyframes = 50;
  // After the step, refine the pose on the already triangulated points (reprojection only).
  // Off: on the straight benchmark the refinement pulled steps to 0.2-14 times their length
  // wherever the earlier structure was inconsistent, and the speed check then followed them.
  bool refine_pose_on_structure = false;
  // A key-frame translation more than this angle off the recent steps' direction (either way)
  // is taken for a wrong relative pose and replaced by the recent motion.
  double max_step_direction_change_deg = 30.0;
  // A step length more than this factor off the median speed of the last speed_history steps
  // is not taken; the next source (structure, then that speed) is.
  double max_step_change = 2.0;
  int speed_history = 10;
  // Triangulate every track seen at least twice in a window anew from the window's current
  // poses before the adjustment (false: only the points triangulated when the track first
  // parted by min_triangulation_angle_deg, never again). Observations that then reproject
  // more than max_window_start_error_px away start as outliers.
  bool retriangulate_in_window = true;
  double max_window_start_error_px = 10.0;
  // Tie each straight window's cylinder to the axis of the last applied window in the same
  // section (CylinderAxisPriorError; sigmas in `window`), across tracking resets too: the
  // pipe is one straight cylinder, and free local cylinders let the heading drift (first 340 frames
  // of the straight benchmark: optical-axis drift 12.9 -> 1.5 degrees, docs/fisheye_mapping.md).
  bool axis_prior = true;
  // A window whose path length changes by more than this factor is dropped (degenerate).
  double max_window_length_change = 1.5;
  // ... or whose fastest key-frame step is more than this factor over its median speed (the
  // crawler moves at a nearly constant speed; the degenerate solution that keeps the path
  // length bunches the cameras and puts the travel into a few steps).
  double max_window_speed_ratio = 4.0;
  // A window is applied only when it converged: image RMS below max_window_rms_px and, with
  // the cylinder, its points on the wall to max_window_cylinder_rms * r (RMS). Its cylinder
  // then gives the axis for the following step lengths.
  double max_window_rms_px = 1.5;
  // 0.05 r: windows at 5-7 mm with sub-pixel image RMS were sound; rejecting them left the
  // rotation to the chained relative poses (first 340 frames: -10.3 % at 0.025, -2.8 % at 0.05).
  double max_window_cylinder_rms = 0.05;
  // After this many unusable frames in a row, tracking starts over from the next frame.
  int max_failures_in_row = 5;
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

struct FisheyeWindowRecord {
  int section = 0;
  int first_keyframe = 0;
  int last_keyframe = 0;
  int points = 0;
  bool cylinder = true;
  // Why the window was not applied (empty: applied): "image rms", "cylinder rms" (not
  // converged), "path length", "step spread" (degenerate).
  std::string rejection;
  double length_ratio = 1.0;  // adjusted / chained path length through the window
  StraightWindowSummary summary;
};

struct FisheyeFrameFailure {
  int index = 0;
  std::string name;
  std::string reason;
};

struct SparsePoint {
  Eigen::Vector3d position;
  int section = 0;
};

struct FisheyeMappingResult {
  Trajectory trajectory;           // every frame (non-key frames interpolated between key frames)
  Trajectory keyframe_trajectory;  // key frames
  std::vector<FisheyeKeyframe> keyframes;
  std::vector<FisheyeSection> sections;
  std::vector<FisheyeWindowRecord> windows;
  std::vector<SparsePoint> points;
  std::vector<FisheyeFrameFailure> failed_frames;
  std::vector<std::string> unreadable_frames;
  int frames = 0;
  int tracking_resets = 0;
  // Wall seconds of the tracking and the classification, and CPU seconds of the whole process
  // over them (every thread: the image read-ahead, OpenCV's workers, and the odometry's thread,
  // which runs meanwhile). Load on a shared machine changes the CPU seconds less than the wall
  // seconds, but not nothing: up to 20 % between runs of one binary on the first 340 straight
  // frames.
  double tracking_seconds = 0.0;
  double classification_seconds = 0.0;
  double tracking_cpu_seconds = 0.0;
  double classification_cpu_seconds = 0.0;
  // The odometry's thread: wall seconds it worked, its own CPU seconds (not those of Ceres's
  // extra workers), and the wall seconds the run waited for it after the last frame.
  double odometry_seconds = 0.0;
  double odometry_cpu_seconds = 0.0;
  double odometry_wait_seconds = 0.0;
};

FisheyeMappingResult RunFisheyeMapping(const DatasetManifest& manifest, const Camera& camera,
                                       const FisheyeMappingOptions& options);

}  // namespace pipescope
