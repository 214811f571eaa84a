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
};

// The mean of each factor x factor block (the incomplete last row and column of blocks are
// dropped): a full-resolution pixel x lands on (x + 0.5) / factor - 0.5, so a shift scales by
// exactly 1 / factor. `factor` 1 returns `image` itself.
cv::Mat DownsampleByBlockMean(const cv::Mat& image, int factor);

class DenseFramePreparation {
 public:
  // `gain_mask` may be empty (no correction). Throws InputError when the mask's size differs
  // from the camera's or the factor is not in 1..16.
  DenseFramePreparation(const Camera& camera, const cv::Mat& gain_mask,
                        const DenseFrameOptions& options);

  // `grey`: CV_32F in 8-bit grey levels, the camera's size. Returns the gain-corrected,
  // undistorted, downsampled frame (CV_32F).
  cv::Mat Prepare(const cv::Mat& grey) const;

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
