#pragma once

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "pipescope/camera/camera.h"

namespace pipescope {

// The focal length of a camera at its principal point, in pixels: fx for pinhole-radtan and
// kannala-brandt, k1 for fisheye-poly (dr/dtheta at theta = 0, 001 eq. 1). The undistorted
// perspective image uses it, so image scale at the centre is unchanged.
double CentralFocalLengthPx(const Camera& camera);

// The principal point of a camera, in pixels.
cv::Point2d PrincipalPoint(const Camera& camera);

// Rectifies images of one camera to a distortion-free perspective image, the image the dense
// methods register (000 §4.2): same size, focal length CentralFocalLengthPx, same principal
// point. The remap tables are built once in the constructor and reused for every frame.
// An optional resampling of the rectified image line by line along one axis: rectified pixel
// (x, y) samples the perspective image at (c.x + factors[y] (x - c.x), y) when `along_x` (one
// factor per row), or at (x, c.y + factors[x] (y - c.y)) otherwise (one per column), c the
// principal point. Empty: none. image/foreshortening.h uses it to give every line the same
// image scale along the pipe.
struct LineStretch {
  std::vector<double> factors;
  bool along_x = true;
};

struct UndistorterOptions {
  LineStretch stretch = {};  // none by default
  // > 1: tables for images block-averaged by this factor (a full-resolution pixel x is block
  // pixel (x + 0.5) / downsample - 0.5). Apply() then takes the block-mean image of a frame and
  // returns the rectified image at that resolution: what the full tables and a block mean
  // afterwards give, up to the resampling's blur, with downsample^2 times fewer pixels to remap.
  int downsample = 1;
  // cv::INTER_LINEAR, or cv::INTER_CUBIC, which blurs less: block means carry detail up to
  // their Nyquist rate, which bilinear weights at a fractional position attenuate.
  int interpolation = cv::INTER_LINEAR;
};

class Undistorter {
 public:
  // Throws InputError when the stretch has a factor count other than the camera's rows
  // (along_x) or columns, or the downsample factor is not in 1..16.
  explicit Undistorter(const Camera& camera, const UndistorterOptions& options = {});

  // Rectified copy of `image` (any type cv::remap takes, in its own depth; the camera's size
  // divided by the downsample factor), interpolated with cv::remap's 1/32 px weight quantisation;
  // pixels whose ray the camera cannot see are 0.
  cv::Mat Apply(const cv::Mat& image) const;

  // The rectified image's camera: pinhole-radtan without distortion.
  const Camera& rectified_camera() const { return rectified_; }
  // The pixel of the original image that a rectified pixel samples (for tests and diagnostics),
  // both at the downsampled resolution.
  cv::Point2f SourcePixel(int x, int y) const {
    return {map_x_.at<float>(y, x), map_y_.at<float>(y, x)};
  }

 private:
  Camera rectified_;
  cv::Mat map_x_;
  cv::Mat map_y_;
  // The same tables in cv::remap's fixed-point form (integer pixel and 1/32 px fraction):
  // the same output as the float tables without converting them on every call.
  cv::Mat fixed_map_xy_;
  cv::Mat fixed_map_fraction_;
  int interpolation_;
};

}  // namespace pipescope
