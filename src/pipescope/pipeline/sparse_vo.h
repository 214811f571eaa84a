#pragma once

#include <map>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "pipescope/camera/camera.h"
#include "pipescope/estimation/sparse_odometer.h"
#include "pipescope/feature/sparse_features.h"
#include "pipescope/geometry/camera_mount.h"
#include "pipescope/io/dataset.h"
#include "pipescope/io/trajectory.h"
#include "pipescope/pipeline/wall_distance_statement.h"

namespace pipescope {

// Sparse monocular visual odometry constrained to a cylinder of known radius (000 §5).
struct SparseVoOptions {
  SparseFeatureOptions features;
  SparseOdometerOptions odometer;
  // When the start's wall distance is measured (wall_distance_m or the reference scale) and the
  // view cannot measure it (WallDistanceObservability), hold the first key frame's position
  // across the pipe there, in the first window adjustment and instead of §5.3.2's estimate of
  // C_X, C_Y. Through a narrow lens (steel-16in: 25 degrees) the reprojections see the wall
  // distance only through the wall's slight curvature; estimated, it follows the keypoints'
  // localisation bias by millimetres. A wide view measures it better than the start's
  // measurement, which is off by where the crawler stood (docs/conditions.md: 6-inch, a start
  // 1.6 mm off, 0.919 % held against 0.023 % free).
  bool hold_measured_start = true;
  // Whether the cross-section anchor (SparseOdometerOptions' window.cross_section_anchor_sigma_m)
  // applies also where the view measures the wall distance. Off: there the images place the
  // camera across the pipe, and the anchor only pulls that place towards the start's (6-inch
  // matrix, five seeds, refined matches: sheen worst 0.273 % anchored, 0.197 % free; wander
  // 0.090 % and 0.102 %; docs/sparse_vo.md). A narrow view keeps the anchor (16-inch, 25°: issue
  // 22's independent rendering 1.54 % without it, 1.25 % with it).
  bool anchor_where_view_measures = false;
  // Fewest inlier correspondences a frame needs to be localised at all.
  int min_correspondences = 12;
  // After this many frames in a row fail against the key frame (a stretch of wall too plain to
  // match), the next frame with enough keypoints restarts the chain at a pose predicted at the
  // last measured speed (SparseOdometer::RestartAt); the failed frames have no pose and the
  // restart's frame counts as predicted. 0: never (the run stays lost).
  int restart_after_failed_frames = 5;
  // A run whose key frames move farther than this share of the radius across the pipe from the
  // first is called unreliable: the images did not hold the camera's distance to the wall (a
  // crawler is centred by its wheels; measured wander stays within 5 %), so the scale is not to
  // be trusted. 0: no check.
  double max_cross_section_excursion = 0.25;
  // Where the view cannot measure the wall distance (WallDistanceStatement), a run whose camera
  // strays more than this share of the wall distance across the pipe is called unreliable: its
  // scale follows that excursion, which the images could not confirm (docs/conditions.md: a
  // 16-inch run 2.2 % off). 0: no check.
  double max_unobserved_excursion = 0.02;
  // A run whose key frames track a median of fewer keypoints than this is called unreliable:
  // too little structure to measure the wall distance (half of 000's 150 correspondences a
  // key-frame span keeps; pipeline/sparse_vo_verdict.h). 0: no check.
  int min_median_tracked = 75;
  CameraMount mount;
  // Distance from the start camera to the wall it faces (metres): 000's "measured manually"
  // offset. 0 = from the reference scale (f / zeta) when the dataset has one, else the radius
  // (camera on the axis).
  double wall_distance_m = 0.0;
  // Read frames and extract their features on a second thread, one frame ahead (beyond 000;
  // same results, the machine's second core used).
  bool pipelined = true;
  double max_saturated_fraction = 0.2;
  double saturation_level = 250.0;
  bool build_mosaic = true;
  // Mosaic cell (metres); 0 = the camera's ground resolution at the start (wall distance / f).
  double mosaic_pixel_m = 0.0;
  // Frames added to the mosaic are at least this many cells apart along the pipe.
  double mosaic_spacing_cells = 50.0;
};

struct SparseFrameRecord {
  std::size_t index = 0;
  double timestamp = 0.0;
  std::string name;
  int keypoints = 0;
  int matches = 0;  // ratio test + mutual check, to the key frame
  int inliers = 0;  // after five-point RANSAC
  bool key_frame = false;
  bool predicted = false;  // a restart's frame: its pose continues the last measured speed
  std::string failure;     // why the frame has no pose; empty when localised
};

struct SparseVoResult {
  Trajectory trajectory;  // every localised frame, world_from_cam, pipe frame (axis Z)
  Trajectory key_frames;
  std::vector<SparseFrameRecord> frames;
  std::vector<std::string> skipped_frames;  // unreadable
  std::vector<Eigen::Vector3d> points;      // one per track seen in >= 2 key frames (pipe frame)
  SparseOdometerSummary summary;            // what the back end did
  cv::Mat mosaic;  // unrolled (CV_32F, NaN where unseen); rows along s = r phi, columns along h
  double mosaic_pixel_m = 0.0;
  cv::Point2d mosaic_origin_m;  // (h, s) of cell (0, 0)
  double odometry_seconds = 0.0;
  // Where the odometry time went: "read" (decoding, gain correction), "features_harris",
  // "features_sift" (on the reader thread when pipelined), "matching"
  // (descriptors), "ransac", "initial_position", "window_adjustment", "refinement"; wall
  // seconds, and CPU seconds of the thread that ran the stage (OpenCV's worker threads not
  // included). odometry_cpu_seconds: CPU seconds of the whole process over the odometry.
  StageTimes stage_times;
  double odometry_cpu_seconds = 0.0;
  // The unrolled mosaic's pass after the odometry: wall seconds, CPU seconds of the process.
  double mosaic_seconds = 0.0;
  double mosaic_cpu_seconds = 0.0;
  // Whether the view lets the window adjustment measure the wall distance, or the scale holds
  // the start's.
  WallDistanceStatement wall_distance;
  // The farthest any key frame's estimated place in the cross-section is from the first's, m.
  double cross_section_excursion_m = 0.0;
  // The σ (m) of the cross-section anchor the window adjustments used; 0: none (no measured
  // start, or a view that measures the wall distance; SparseVoOptions::anchor_where_view_measures).
  double cross_section_anchor_sigma_m = 0.0;
};

// Runs sparse VO over the dataset's frames; needs pipe.inner_radius_m. The dataset's gain mask
// is applied when it names one. Throws InputError naming the missing key or a bad option.
SparseVoResult RunSparseVo(const DatasetManifest& manifest, const Camera& camera,
                           const SparseVoOptions& options);

}  // namespace pipescope
