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

// The mean of each factor x factor block of `image` times `weight` (the incomplete last row and
// column of blocks are dropped), times `scale`: a full-resolution pixel x lands on
// (x + 0.5) / factor - 0.5, so a shift scales by exactly 1 / factor. `image`: one channel,
// CV_8U, CV_16U or CV_32F; `weight`: CV_32F of the same size, or empty for 1. Returns CV_32F.
// One pass over the frame: gain correction and downsampling fold into it.
cv::Mat WeightedBlockMean(const cv::Mat& image, const cv::Mat& weight, int factor,
                          float scale = 1.0f);

// The plain block mean: WeightedBlockMean without weights; `factor` 1 returns `image` itself.
cv::Mat DownsampleByBlockMean(const cv::Mat& image, int factor);

// The prepared frames' size and principal point for `camera` downsampled by `factor` (the
// rectified camera keeps the camera's size and principal point; the block mean maps a
// full-resolution pixel x to (x + 0.5) / factor - 0.5). Known before any tables are built, so
// a pipeline can choose its band first. Throws InputError when the factor is not in 1..16.
cv::Size PreparedFrameSize(const Camera& camera, int factor);
cv::Point2d PreparedFramePrincipalPoint(const Camera& camera, int factor);

class DenseFramePreparation {
 public:
  // `gain_mask` may be empty (no correction); `stretch` resamples the undistorted image line by
  // line (image/undistortion.h; image/foreshortening.h). Throws InputError when the mask's
  // size differs from the camera's or the factor is not in 1..16.
  DenseFramePreparation(const Camera& camera, const cv::Mat& gain_mask,
                        const DenseFrameOptions& options, const LineStretch& stretch = {});

  // `grey`: one channel, the camera's size, CV_8U, CV_16U (scaled to 8-bit grey levels) or
  // CV_32F in 8-bit grey levels. Returns the gain-corrected, undistorted, downsampled frame
  // (CV_32F). 000 §4.2's order with the last two steps swapped: the frame is gain-corrected and
  // block-averaged in one pass, and the block means are undistorted with tables built for that
  // resolution, so the remap touches downsample^2 times fewer pixels. The distortion is smooth
  // over a block, so this differs from undistorting first only by the low-resolution resampling,
  // bicubic so that it blurs the block means' detail little. Measured on the short steel-16in
  // run of dense_vo_test: bilinear here moved dense-hybrid's error from 0.008 % to 0.038 %,
  // bicubic gives 0.013 %.
  cv::Mat Prepare(const cv::Mat& grey) const;

  // The gain-corrected frame box-filtered by the factor without undistortion (Prepare()'s first
  // pass, and the input of dense-unrolled, which resamples the distorted frame itself). Same
  // `grey` as Prepare().
  cv::Mat CorrectAndDownsample(const cv::Mat& grey) const;

  cv::Point2d PreparedPrincipalPoint() const {
    return PreparedFramePrincipalPoint(undistorter_.rectified_camera(), options_.downsample);
  }
  cv::Size PreparedSize() const {
    return PreparedFrameSize(undistorter_.rectified_camera(), options_.downsample);
  }
  int downsample() const { return options_.downsample; }

 private:
  Undistorter undistorter_;
  cv::Mat correction_;  // gain correction factors, empty without a mask
  DenseFrameOptions options_;
};

}  // namespace pipescope
