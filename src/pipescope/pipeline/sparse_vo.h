#pragma once

#include <map>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "pipescope/camera/camera.h"
#include "pipescope/estimation/axial_step.h"
#include "pipescope/estimation/global_scale.h"
#include "pipescope/estimation/initial_position.h"
#include "pipescope/estimation/pose_refinement.h"
#include "pipescope/estimation/window_adjustment.h"
#include "pipescope/feature/descriptor_matching.h"
#include "pipescope/feature/key_frame_selection.h"
#include "pipescope/feature/region_harris.h"
#include "pipescope/feature/sift_description.h"
#include "pipescope/geometry/five_point_ransac.h"
#include "pipescope/io/dataset.h"
#include "pipescope/io/trajectory.h"
#include "pipescope/pipeline/dense_motion_model.h"

namespace pipescope {

// Sparse monocular visual odometry constrained to a cylinder of known radius (000 §5).
// 000's region Harris with sigma_W = 2 instead of 3 (beyond 000, measured: docs/sparse_vo.md,
// steel-16in 0.731 % -> 0.095 %, steel-6in 0.068 % -> 0.016 %).
RegionHarrisOptions SparseVoRegionHarrisOptions();

// The window adjustment with the cross-section anchor on (beyond 000, which holds C_X, C_Y
// constant after §5.3.2): every free key frame's place across the pipe is held to the measured
// start with sigma 1 mm, i.e. the crawler is taken to be centred over metres of travel. Where the
// lens sees too little of the wall's curvature (steel-16in) the wall distance, and with it the
// scale, otherwise wanders and keeps any error of the measured start (docs/sparse_vo.md,
// "Holding the wall distance").
WindowAdjustmentOptions SparseVoWindowOptions();

struct SparseVoOptions {
  RegionHarrisOptions harris = SparseVoRegionHarrisOptions();
  SiftDescriptionOptions sift;
  DescriptorMatchingOptions matching;
  FivePointRansacOptions ransac;  // focal_length_px is taken from the camera
  KeyFrameOptions key_frames;
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
  // When the start's wall distance is measured (wall_distance_m or the reference scale), hold
  // the first key frame's position across the pipe there, in the first window adjustment and
  // instead of §5.3.2's estimate of C_X, C_Y. Through a narrow lens (steel-16in: 25 degrees)
  // the reprojections see the wall distance, and so the scale, only through the wall's slight
  // curvature; estimated, it follows the keypoints' localisation bias by millimetres.
  bool hold_measured_start = true;
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
  // Fewest inlier correspondences a frame needs to be localised at all.
  int min_correspondences = 12;
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
  std::string failure;  // why the frame has no pose; empty when localised
};

struct SparseKeyFrameRecord {
  std::size_t frame_index = 0;
  int keypoints = 0;
  int tracked = 0;  // keypoints continuing a track of an earlier key frame
};

struct SparseVoResult {
  Trajectory trajectory;  // every localised frame, world_from_cam, pipe frame (axis Z)
  Trajectory key_frames;
  std::vector<SparseFrameRecord> frames;
  std::vector<SparseKeyFrameRecord> key_frame_records;
  std::vector<std::string> skipped_frames;  // unreadable
  std::vector<Eigen::Vector3d> points;      // one per track seen in >= 2 key frames (pipe frame)
  Eigen::Vector2d initial_c_xy = Eigen::Vector2d::Zero();
  Eigen::Vector2d optimised_c_xy = Eigen::Vector2d::Zero();
  double initial_reprojection_rms_px = 0.0;
  double optimised_reprojection_rms_px = 0.0;
  int refinements = 0;
  int window_adjustments = 0;
  int revisits = 0;  // key frames matched to an older key frame of the same place (revisit)
  GlobalScaleResult global_scale;
  cv::Mat mosaic;  // unrolled (CV_32F, NaN where unseen); rows along s = r phi, columns along h
  double mosaic_pixel_m = 0.0;
  cv::Point2d mosaic_origin_m;  // (h, s) of cell (0, 0)
  double odometry_seconds = 0.0;
  // Where the odometry time went: "read" (decoding, gain correction), "features_harris",
  // "features_sift" (on the reader thread when pipelined), "matching"
  // (descriptors), "ransac", "initial_position", "window_adjustment", "refinement"; wall
  // seconds, and CPU seconds of the thread that ran the stage (OpenCV's worker threads not
  // included). odometry_cpu_seconds: CPU seconds of the whole process over the odometry.
  std::map<std::string, double> stage_seconds;
  std::map<std::string, double> stage_cpu_seconds;
  double odometry_cpu_seconds = 0.0;
  // The unrolled mosaic's pass after the odometry: wall seconds, CPU seconds of the process.
  double mosaic_seconds = 0.0;
  double mosaic_cpu_seconds = 0.0;
};

// Runs sparse VO over the dataset's frames; needs pipe.inner_radius_m. The dataset's gain mask
// is applied when it names one. Throws InputError naming the missing key or a bad option.
SparseVoResult RunSparseVo(const DatasetManifest& manifest, const Camera& camera,
                           const SparseVoOptions& options);

}  // namespace pipescope
