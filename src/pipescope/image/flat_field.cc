#include "pipescope/image/flat_field.h"

#include <opencv2/imgproc.hpp>

namespace pipescope {

cv::Mat FlatFieldedGrey8(const cv::Mat& grey8, double sigma_px) {
  if (sigma_px <= 0.0) return grey8;
  cv::Mat grey;
  grey8.convertTo(grey, CV_32F);
  // The shading is smooth: blur a quarter-size copy and bring it back, a sixteenth of the cost of
  // a full-size blur with a kernel this wide.
  const int shrink = sigma_px >= 8.0 ? 4 : 1;
  cv::Mat small, shading;
  cv::resize(grey, small, cv::Size(grey.cols / shrink, grey.rows / shrink), 0, 0, cv::INTER_AREA);
  cv::GaussianBlur(small, small, cv::Size(), sigma_px / shrink);
  cv::resize(small, shading, grey.size(), 0, 0, cv::INTER_LINEAR);
  // The floor keeps the unlit depth from amplifying its noise without bound.
  cv::Mat albedo = 128.0 * grey / cv::max(shading, 4.0), flat;
  albedo.convertTo(flat, CV_8U);
  return flat;
}

}  // namespace pipescope
