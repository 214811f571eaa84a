#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "pipescope/camera/camera.h"
#include "pipescope/estimation/dense_odometer.h"
#include "pipescope/io/dataset.h"
#include "pipescope/io/trajectory.h"
#include "pipescope/pipeline/wall_distance_statement.h"

namespace pipescope {

struct DenseVoResult {
  Trajectory trajectory;  // world_from_cam of every frame, pipe frame (axis Z)
  std::vector<DenseFrameRecord> frames;
  std::vector<std::string> skipped_frames;  // unreadable
  int failed_pairs = 0;
  // The appearance map (CV_32F, NaN where no frame contributed): image space for the planar
  // methods (000 Fig. 14/16), the unrolled wall (h along columns, s = r phi along rows) for
  // dense-unrolled. Empty when options.build_mosaic is false.
  cv::Mat mosaic;
  double mosaic_pixel_m = 0.0;  // dense-unrolled: the unrolled mosaic's cell size
  // dense-unrolled: (h, s) of the mosaic's cell (0, 0), metres.
  cv::Point2d mosaic_origin_m;
  // Wall-clock seconds of the frame loop, and its stages: "reading" (decoding the frames),
  // "preparing" (gain, undistortion or unrolling, downsampling), "registering" the pairs.
  double registration_seconds = 0.0;
  StageTimes stage_times;
  // CPU seconds of the frame loop's own thread (frames are decoded on another): the cost of
  // preparing and registering on one core, unaffected by a busy machine's waits.
  double loop_cpu_seconds = 0.0;
  // The start's wall distance (the reference scale's), whether the method measures it along the
  // run (dense-unrolled where the view sees the wall's curvature) and whether the view could.
  WallDistanceStatement wall_distance;
  // dense-unrolled measuring the cross-section: the key frames whose alignment was taken, and
  // those whose was not (they kept the place of the key frame before).
  int cross_section_alignments = 0;
  int cross_section_rejections = 0;
  std::vector<double> cross_section_sigmas_m;  // DenseOdometer::cross_section_sigmas()
  int cross_section_faint = 0;                  // rejections: frames mostly noise
  // The key frame from which the frames were aligned blurred (too faint at full detail;
  // DenseOdometerOptions::cross_section_faint_smooth_px), -1: never.
  int cross_section_blurred_from = -1;
  // Set when most key frames' alignments were not taken; wall_distance then says the method
  // did not measure it.
  std::string cross_section_warning;
};

// Runs dense VO over the dataset's frames. The reference scale (reference_scale_px_per_m) is
// required, and the pipe radius for dense-unrolled; the dataset's gain mask is applied when it
// names one. Throws InputError naming the missing key or bad option.
DenseVoResult RunDenseVo(const DatasetManifest& manifest, const Camera& camera,
                         const DenseOdometerOptions& options);

}  // namespace pipescope
