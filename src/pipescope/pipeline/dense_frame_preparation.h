#pragma once

#include <opencv2/core.hpp>

#include "pipescope/camera/camera.h"
#include "pipescope/image/undistortion.h"

namespace pipescope {

// The preprocessing of 000 §4.2 before dense registration: gain correction (§3.2), undistortion
// to a perspective image (remap tables built once), and downsampling by an integer factor (000
// registers quarter-resolution frames: 256x192 for pipe 1, 160x120 for pipe 2).
struct DenseFrameOptions {
  int downsample = 4;  // 1 = full resolution
  // Pixels at or above this 8-bit grey level count as saturated (specular highlights, 000 Fig. 12).
  double saturation_level = 250.0;
};

struct PreparedFrame {
  cv::Mat image;                  // CV_32F, gain-corrected, undistorted, downsampled
  double saturated_fraction = 0;  // of the raw frame's pixels
};

class DenseFramePreparation {
 public:
  // `gain_mask` may be empty (no correction). Throws InputError when the mask's size differs
  // from the camera's or the factor is not in 1..16.
  DenseFramePreparation(const Camera& camera, const cv::Mat& gain_mask,
                        const DenseFrameOptions& options);

  // `grey`: CV_32F in 8-bit grey levels, the camera's size.
  PreparedFrame Prepare(const cv::Mat& grey) const;

  // The reference scale at the prepared frames' resolution: zeta / downsample.
  double ScaleAtPreparedResolution(double zeta_px_per_m) const {
    return zeta_px_per_m / options_.downsample;
  }
  // The principal point of the prepared frames, in their pixels (the downsampling maps a
  // full-resolution pixel x to (x + 0.5) / factor - 0.5).
  cv::Point2d PreparedPrincipalPoint() const;
  cv::Size PreparedSize() const;
  int downsample() const { return options_.downsample; }

 private:
  Undistorter undistorter_;
  cv::Mat gain_mask_;
  DenseFrameOptions options_;
};

}  // namespace pipescope
