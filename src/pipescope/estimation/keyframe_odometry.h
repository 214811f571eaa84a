#pragma once

#include <Eigen/Geometry>
#include <string>
#include <unordered_map>
#include <vector>

#include "pipescope/camera/camera.h"
#include "pipescope/estimation/straight_window_adjustment.h"
#include "pipescope/feature/feature_tracker.h"
#include "pipescope/geometry/pipe_cylinder.h"
#include "pipescope/image/settled_sections.h"

namespace pipescope {

struct KeyframeOdometryOptions {
  StraightWindowOptions window;  // radius_m comes from the dataset
  // 001 runs the SBA every 50 key frames over the last 100. Here the chain of relative poses
  // between windows drifts in scale far more than 001's did (the templates' relative rotations
  // are off by about a degree at 1 cm baselines), so the defaults adjust every 20 key frames
  // over the last 50; 50 / 100 is a --config away (window_interval, window_size). On the first
  // 200 frames of the straight benchmark, 50 / 100 gave a 78.5 % distance error, 10 / 50 gave
  // 15 % (templates). With the features followed (lucas-kanade) 20 / 50 takes the windows' time
  // down by 40 % and measured as well as 10 / 50 or better (straight −0.012 against −0.026 %,
  // route A's first 2800 frames T1-T4 1.27 against 2.00 %), the templates about the same
  // (docs/fisheye_mapping.md, Window schedule).
  int window_interval = 20;
  int window_size = 50;
  // A window of fewer key frames (a short section, or just after a tracking reset) fits its
  // cylinder to too few of them and is not run (before the interval became 20 it was the
  // interval, 10).
  int min_window_keyframes = 10;
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
  // A key-frame step whose median parallax (the angle between a feature's two bearings once the
  // relative rotation is taken out) is below this stood still: its translation direction is
  // noise, so the camera keeps its place and takes the measured rotation. About twice the
  // tracker's inlier threshold (0.004 rad, about 1.2 px on 001's 1280x960 lens), the parallax's
  // noise.
  double stationary_parallax_rad = 0.008;
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
};

// How a key frame's step was fixed, for run.json.
struct KeyframeStepRecord {
  int points_used = 0;              // triangulated points seen that fixed the relative scale
  bool direction_rejected = false;  // translation off the recent direction: motion continued
  bool stationary = false;          // no parallax: the camera stood still (measured, not predicted)
};

struct OdometryWindowRecord {
  int section = 0;
  int first_keyframe = 0;
  int last_keyframe = 0;
  int points = 0;
  bool straight = true;  // in a straight section (not a T-intersection)
  bool cylinder = true;  // fitted the straight cylinder (straight, and use_cylinder)
  // Why the window was not applied (empty: applied): "image rms", "cylinder rms" (not
  // converged), "path length", "step spread" (degenerate).
  std::string rejection;
  double length_ratio = 1.0;  // adjusted / chained path length through the window
  StraightWindowSummary summary;
};

struct SparsePoint {
  Eigen::Vector3d position;
  int section = 0;     // of the track's first observation
  long track_id = -1;  // the feature track it was triangulated from (-1: none)
};

// Visual odometry over tracked fisheye key frames in straight sections and T-intersections
// (001 §III-C), one key frame at a time in order: the direction from the relative pose on the
// sphere (RANSAC), the step length from the pipe radius (two-view points put on the wall, eq. 6) or
// from earlier structure, triangulation, and every window_interval key frames the sliding-window
// bundle adjustment with the local straight cylinder (eq. 2-6). A key frame's pose and windows use
// only the key frames before it and its settled section, so the odometry can run behind the
// tracking.
class KeyframeOdometry {
 public:
  KeyframeOdometry(const Camera& camera, const KeyframeOdometryOptions& options)
      : camera_(camera), options_(options) {}

  // The next key frame, with its settled section (SettledSections).
  void Add(TrackedKeyframe keyframe, const KeyframeSection& section);

  int KeyframeCount() const { return static_cast<int>(tracked_.size()); }
  // Key frame k's pose, camera to world (the world is the first key frame's camera frame).
  Eigen::Isometry3d WorldFromCam(int k) const { return cam_from_world_[k].inverse(); }
  const KeyframeStepRecord& StepRecord(int k) const { return steps_[k]; }
  const std::vector<OdometryWindowRecord>& windows() const { return windows_; }
  // The triangulated points, each with the section of the key frame that first saw it.
  std::vector<SparsePoint> Points() const;

  struct Observation {
    int keyframe;
    Eigen::Vector2d pixel;
    Eigen::Vector3d bearing;
  };
  // The observations in key frames first..last of every track seen there at least
  // `min_observations` times: the input of the passes that run after the odometry (the
  // T-intersections, 001 §III-D).
  // `ids`, when given, receives each returned track's id.
  std::vector<std::vector<Observation>> TracksIn(int first, int last, int min_observations,
                                                 std::vector<long>* ids = nullptr) const;
  // The key frame that first saw the feature track `track_id`, or -1 when there is no such
  // track: a point moves with it when loop closure moves the key frames (001 §III-E).
  int FirstKeyframeOfTrack(long track_id) const;

 private:
  struct Track {
    std::vector<Observation> observations;
    bool has_point = false;
    Eigen::Vector3d point = Eigen::Vector3d::Zero();
  };

  void AddObservations(int k);
  void EstimatePose(int k);
  Eigen::Vector3d ReferenceDirection() const;
  double MedianParallax(int k) const;
  static const Observation* InPreviousKeyframe(const Track& track, int k);
  double PathLength(int first, int last) const;
  static double PathLength(const std::vector<Eigen::Isometry3d>& cam_from_world);
  double MaxSpeedOverMedian(const std::vector<Eigen::Isometry3d>& cam_from_world, int first) const;
  PipeAxis AxisInCamera(int k) const;
  void Triangulate(int k);
  bool TriangulateInWindow(const std::vector<const Observation*>& observations,
                           Eigen::Vector3d* point) const;
  void AdjustWindow(int first, int last, int section, bool cylinder);

  const Camera& camera_;
  const KeyframeOdometryOptions options_;
  std::vector<TrackedKeyframe> tracked_;
  std::vector<KeyframeSection> sections_;  // per key frame
  std::vector<KeyframeStepRecord> steps_;  // per key frame
  std::vector<OdometryWindowRecord> windows_;
  std::vector<Eigen::Isometry3d> cam_from_world_;
  std::unordered_map<long, Track> tracks_;
  // The last key-frame steps' speeds (metres a frame) and the last step's direction (in the
  // camera frame): the motion continued across a tracking reset, the step length when nothing
  // else fixes it, and the check of the ones that do.
  std::vector<double> recent_speeds_;
  Eigen::Vector3d last_direction_ = Eigen::Vector3d::UnitZ();
  std::vector<Eigen::Vector3d> recent_directions_;  // of the steps taken from relative poses
  int segment_start_ = 0;                           // first key frame since the last tracking reset
  PipeAxis axis_world_;                             // the current straight section's axis
  int axis_section_ = -1;
  int axis_keyframe_ = 0;  // key frame of the last applied window (or the section's start)
  // The axis of the last applied window and its section (the prior of the next window there;
  // axis_world_ may instead hold a per-step fit or the section's entry guess).
  PipeAxis window_axis_world_;
  int window_axis_section_ = -1;
};

}  // namespace pipescope
