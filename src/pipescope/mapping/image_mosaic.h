#pragma once

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pipescope/mapping/mean_accumulator.h"

namespace pipescope {

// The image-space stitched map of the dense methods (000 §6.1, Fig. 14 and 16): undistorted,
// gain-corrected frames placed at their registered image offsets, each mosaic pixel the mean of
// the frames covering it. As in the paper only frames at least min_spacing_px from the last
// frame used contribute, so a slow crawler does not weight the map towards where it lingered.
class ImageMosaic {
 public:
  // 000 §6.1: "separated by an x translation magnitude of at least 50 pixels".
  explicit ImageMosaic(double min_spacing_px = 50.0);

  // Places `frame` (one channel, converted to CV_32F) with its pixel (0, 0) at `offset_px` in
  // mosaic coordinates, resampled bilinearly onto the integer mosaic grid. Pixels where
  // `valid_mask` (CV_8U, frame size; empty = all) is 0 or the value is not finite are left
  // out. Returns false, adding nothing, when the offset lies closer than min_spacing_px
  // (Euclidean) to the last frame used; the first frame is always used.
  bool Add(const cv::Mat& frame, cv::Point2d offset_px, const cv::Mat& valid_mask = cv::Mat());

  // The mean of the contributing frames over Bounds() (CV_32F), NaN where none contributed.
  cv::Mat Render() const;
  // Mosaic coordinates of the cells Render() covers: its pixel (0, 0) is Bounds().tl().
  cv::Rect Bounds() const { return accumulator_.Bounds(); }

  int frames_used() const { return frames_used_; }

 private:
  double min_spacing_px_;
  MeanAccumulator accumulator_;
  int frames_used_ = 0;
  cv::Point2d last_offset_px_;
};

// Where frame k lands in an image mosaic started by frame 0, from the camera poses: a camera
// moving by d (metres, in camera 0's frame) sees a wall at the reference distance shift by
// -zeta d in the image, so frame k's pixel (0, 0) shows what frame 0 sees at +zeta (d_x, d_y)
// (camera x, y are image x, y; 000 eq. 18-19 read backwards). `px_per_m` is the reference
// scale zeta of 000 §3.3.
cv::Point2d ImageOffsetFromPoses(const Eigen::Isometry3d& world_from_first_cam,
                                 const Eigen::Isometry3d& world_from_cam, double px_per_m);

}  // namespace pipescope
