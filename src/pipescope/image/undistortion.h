#pragma once

#include <opencv2/core.hpp>
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
// principal point. Empty: none. pipeline/foreshortening.h uses it to give every line the same
// image scale along the pipe.
struct LineStretch {
  std::vector<double> factors;
  bool along_x = true;
};

class Undistorter {
 public:
  // Throws InputError when `stretch` has a factor count other than the camera's rows (along_x)
  // or columns.
  explicit Undistorter(const Camera& camera, const LineStretch& stretch = {});

  // Rectified copy of `image` (any type cv::remap takes, in its own depth), bilinear with
  // cv::remap's 1/32 px weight quantisation; pixels whose ray the camera cannot see are 0.
  cv::Mat Apply(const cv::Mat& image) const;

  // The rectified image's camera: pinhole-radtan without distortion.
  const Camera& rectified_camera() const { return rectified_; }
  // The pixel of the original image that a rectified pixel samples (for tests and diagnostics).
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
};

}  // namespace pipescope
