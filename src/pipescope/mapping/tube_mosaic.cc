#include "pipescope/mapping/tube_mosaic.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/core/utility.hpp>

#include "pipescope/util/error.h"

namespace pipescope {
namespace {

float Bilinear(const cv::Mat& grey, double u, double v) {
  const int x = static_cast<int>(std::floor(u));
  const int y = static_cast<int>(std::floor(v));
  const float fx = static_cast<float>(u - x);
  const float fy = static_cast<float>(v - y);
  const float* row0 = grey.ptr<float>(y);
  const float* row1 = grey.ptr<float>(y + 1);
  return (1 - fy) * ((1 - fx) * row0[x] + fx * row0[x + 1]) +
         fy * ((1 - fx) * row1[x] + fx * row1[x + 1]);
}

}  // namespace

TubeMosaic::TubeMosaic(const TubeCentreline& centreline, double begin_m, double end_m,
                       const TubeMosaicOptions& options)
    : centreline_(centreline), options_(options), begin_m_(begin_m) {
  if (centreline.points.size() < 2) throw InputError("TubeMosaic: the centreline has no segment");
  const double radius = *std::max_element(centreline.radius_m.begin(), centreline.radius_m.end());
  pixel_m_ = options.pixel_m > 0.0 ? options.pixel_m : radius / 100.0;
  const int cols = std::max(1, static_cast<int>(std::ceil((end_m - begin_m) / pixel_m_)));
  const int rows = std::max(4, static_cast<int>(std::round(2.0 * M_PI * radius / pixel_m_)));
  if (static_cast<double>(cols) * rows > 4e8) {
    throw InputError("TubeMosaic: " + std::to_string(cols) + " x " + std::to_string(rows) +
                     " cells is too large; choose a larger cell");
  }
  image_ = cv::Mat(rows, cols, CV_32F, cv::Scalar(std::numeric_limits<float>::quiet_NaN()));
}

void TubeMosaic::AddFrame(const cv::Mat& grey, const Camera& camera,
                          const Eigen::Isometry3d& world_from_cam, double camera_arc_m) {
  const double radius = CentrelineFrameAt(centreline_, camera_arc_m).radius_m;
  const int first = std::max(
      0, static_cast<int>(
             std::floor((camera_arc_m - options_.behind_radii * radius - begin_m_) / pixel_m_)));
  const int last = std::min(
      image_.cols - 1, static_cast<int>(std::ceil(
                           (camera_arc_m + options_.ahead_radii * radius - begin_m_) / pixel_m_)));
  if (first > last) return;
  const Eigen::Isometry3d cam_from_world = world_from_cam.inverse();
  const double low = options_.margin_px;
  const double high_u = grey.cols - 1 - options_.margin_px;
  const double high_v = grey.rows - 1 - options_.margin_px;
  cv::parallel_for_(cv::Range(first, last + 1), [&](const cv::Range& range) {
    for (int col = range.start; col < range.end; ++col) {
      const CentrelineFrame frame =
          CentrelineFrameAt(centreline_, begin_m_ + (col + 0.5) * pixel_m_);
      for (int row = 0; row < image_.rows; ++row) {
        const double phi = 2.0 * M_PI * (row + 0.5) / image_.rows;
        const Eigen::Vector3d wall =
            frame.point +
            frame.radius_m * (std::cos(phi) * frame.normal - std::sin(phi) * frame.binormal);
        Eigen::Vector2d pixel;
        if (camera.Project(cam_from_world * wall, &pixel) != ProjectionStatus::kValid) continue;
        if (pixel.x() < low || pixel.y() < low || pixel.x() > high_u || pixel.y() > high_v)
          continue;
        image_.at<float>(row, col) = Bilinear(grey, pixel.x(), pixel.y());
      }
    }
  });
}

}  // namespace pipescope
