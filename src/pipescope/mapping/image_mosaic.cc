#include "pipescope/mapping/image_mosaic.h"

#include <cmath>

namespace pipescope {

ImageMosaic::ImageMosaic(double min_spacing_px) : min_spacing_px_(min_spacing_px) {}

bool ImageMosaic::Add(const cv::Mat& frame, cv::Point2d offset_px, const cv::Mat& valid_mask) {
  CV_Assert(frame.channels() == 1);
  CV_Assert(valid_mask.empty() ||
            (valid_mask.type() == CV_8U && valid_mask.size() == frame.size()));
  CV_Assert(std::isfinite(offset_px.x) && std::isfinite(offset_px.y));
  if (frames_used_ > 0 && cv::norm(offset_px - last_offset_px_) < min_spacing_px_) return false;
  ++frames_used_;
  last_offset_px_ = offset_px;

  cv::Mat image;
  if (frame.type() == CV_32F) {
    image = frame;
  } else {
    frame.convertTo(image, CV_32F);
  }
  // Mosaic cell (ix + x, iy + y) samples the frame at (x - fx, y - fy): the weights are the same
  // for every pixel, so bilinear resampling is four shifted copies of the frame. Where fx == 0
  // the left taps have weight 0 and are skipped, so integer offsets copy the frame exactly.
  const double ix = std::floor(offset_px.x);
  const double iy = std::floor(offset_px.y);
  const float fx = static_cast<float>(offset_px.x - ix);
  const float fy = static_cast<float>(offset_px.y - iy);
  const int x0 = fx > 0.0f ? 1 : 0;
  const int y0 = fy > 0.0f ? 1 : 0;
  const int width = image.cols - x0;
  const int height = image.rows - y0;
  if (width <= 0 || height <= 0) return true;
  const auto tap = [&](const cv::Mat& source, int dx, int dy) {
    return source(cv::Rect(x0 + dx, y0 + dy, width, height));
  };
  cv::Mat values = (1.0f - fx) * (1.0f - fy) * tap(image, 0, 0);
  cv::Mat mask = valid_mask.empty() ? cv::Mat() : tap(valid_mask, 0, 0).clone();
  const struct {
    int dx, dy;
    float weight;
  } others[] = {{-1, 0, fx * (1.0f - fy)}, {0, -1, (1.0f - fx) * fy}, {-1, -1, fx * fy}};
  for (const auto& other : others) {
    if (other.weight == 0.0f) continue;
    values += other.weight * tap(image, other.dx, other.dy);
    if (!mask.empty()) cv::bitwise_and(mask, tap(valid_mask, other.dx, other.dy), mask);
  }
  accumulator_.Add(values, cv::Point(static_cast<int>(ix) + x0, static_cast<int>(iy) + y0), mask);
  return true;
}

cv::Mat ImageMosaic::Render() const { return accumulator_.Render(accumulator_.Bounds()); }

cv::Point2d ImageOffsetFromPoses(const Eigen::Isometry3d& world_from_first_cam,
                                 const Eigen::Isometry3d& world_from_cam, double px_per_m) {
  const Eigen::Vector3d position = (world_from_first_cam.inverse() * world_from_cam).translation();
  return {px_per_m * position.x(), px_per_m * position.y()};
}

}  // namespace pipescope
