#include "pipescope/feature/region_harris.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace pipescope {
namespace {

// Derivative-of-Gaussian kernels of eq. 31: the Gaussian and its derivative, 3 sigma each side.
void DerivativeOfGaussianKernels(double sigma, cv::Mat* smooth, cv::Mat* derivative) {
  const int half = std::max(1, static_cast<int>(std::ceil(3.0 * sigma)));
  *smooth = cv::Mat(2 * half + 1, 1, CV_32F);
  *derivative = cv::Mat(2 * half + 1, 1, CV_32F);
  double sum = 0.0;
  for (int i = -half; i <= half; ++i) {
    const double g = std::exp(-0.5 * i * i / (sigma * sigma));
    smooth->at<float>(i + half) = static_cast<float>(g);
    sum += g;
  }
  *smooth /= sum;
  // d/dx G = -x / sigma^2 G; cv::sepFilter2D correlates, so the kernel is mirrored (x -> -x).
  for (int i = -half; i <= half; ++i) {
    derivative->at<float>(i + half) =
        static_cast<float>(i / (sigma * sigma) * smooth->at<float>(i + half));
  }
}

}  // namespace

cv::Mat HarrisResponse(const cv::Mat& grey, const RegionHarrisOptions& options) {
  cv::Mat image = grey;
  if (grey.depth() != CV_32F) grey.convertTo(image, CV_32F);
  if (options.box_window_px > 0) {
    cv::Mat response;
    cv::cornerHarris(image, response, options.box_window_px, options.sobel_aperture, options.k);
    return response;
  }
  cv::Mat smooth, derivative;
  DerivativeOfGaussianKernels(options.sigma_derivative_px, &smooth, &derivative);
  cv::Mat ix, iy;
  cv::sepFilter2D(image, ix, CV_32F, derivative, smooth, cv::Point(-1, -1), 0, cv::BORDER_REFLECT);
  cv::sepFilter2D(image, iy, CV_32F, smooth, derivative, cv::Point(-1, -1), 0, cv::BORDER_REFLECT);
  // Eq. 30 with the Gaussian window G(sigma_W): the three gradient products in one pass, each
  // blurred in place, then eq. 28-29 in one pass (Mat expressions would allocate a temporary
  // image per operator).
  cv::Mat ixx(image.size(), CV_32F), iyy(image.size(), CV_32F), ixy(image.size(), CV_32F);
  for (int y = 0; y < image.rows; ++y) {
    const float* gx = ix.ptr<float>(y);
    const float* gy = iy.ptr<float>(y);
    float* xx = ixx.ptr<float>(y);
    float* yy = iyy.ptr<float>(y);
    float* xy = ixy.ptr<float>(y);
    for (int x = 0; x < image.cols; ++x) {
      xx[x] = gx[x] * gx[x];
      yy[x] = gy[x] * gy[x];
      xy[x] = gx[x] * gy[x];
    }
  }
  // Truncated at 3 sigma (OpenCV's default for float images is 4 sigma, a third more taps).
  const int half = std::max(1, static_cast<int>(std::ceil(3.0 * options.sigma_window_px)));
  const cv::Size window(2 * half + 1, 2 * half + 1);
  cv::GaussianBlur(ixx, ixx, window, options.sigma_window_px, 0, cv::BORDER_REFLECT);
  cv::GaussianBlur(iyy, iyy, window, options.sigma_window_px, 0, cv::BORDER_REFLECT);
  cv::GaussianBlur(ixy, ixy, window, options.sigma_window_px, 0, cv::BORDER_REFLECT);
  const float k = static_cast<float>(options.k);
  cv::Mat response = ix;  // reused: the derivatives are no longer needed
  for (int y = 0; y < image.rows; ++y) {
    const float* xx = ixx.ptr<float>(y);
    const float* yy = iyy.ptr<float>(y);
    const float* xy = ixy.ptr<float>(y);
    float* r = response.ptr<float>(y);
    for (int x = 0; x < image.cols; ++x) {
      const float trace = xx[x] + yy[x];
      r[x] = xx[x] * yy[x] - xy[x] * xy[x] - k * trace * trace;
    }
  }
  return response;
}

cv::Point2f QuadraticPeakOffset(const cv::Mat& response, int x, int y) {
  auto c = [&](int dx, int dy) { return static_cast<double>(response.at<float>(y + dy, x + dx)); };
  // Gradient and Hessian of eq. 32 by central differences.
  const double gx = 0.5 * (c(1, 0) - c(-1, 0));
  const double gy = 0.5 * (c(0, 1) - c(0, -1));
  const double hxx = c(1, 0) - 2.0 * c(0, 0) + c(-1, 0);
  const double hyy = c(0, 1) - 2.0 * c(0, 0) + c(0, -1);
  const double hxy = 0.25 * (c(1, 1) - c(1, -1) - c(-1, 1) + c(-1, -1));
  const double det = hxx * hyy - hxy * hxy;
  if (!(hxx < 0.0) || !(det > 0.0)) return {0.f, 0.f};
  // Eq. 34: delta = -H^-1 g.
  const double dx = -(hyy * gx - hxy * gy) / det;
  const double dy = -(-hxy * gx + hxx * gy) / det;
  if (std::abs(dx) > 1.0 || std::abs(dy) > 1.0) return {0.f, 0.f};
  return {static_cast<float>(dx), static_cast<float>(dy)};
}

int RegionCell(const RegionHarrisOptions& options, cv::Size size, int x, int y) {
  const int row = std::min(options.grid_rows - 1, y * options.grid_rows / size.height);
  const int col = std::min(options.grid_cols - 1, x * options.grid_cols / size.width);
  return row * options.grid_cols + col;
}

std::vector<Keypoint> DetectRegionHarris(const cv::Mat& grey, const RegionHarrisOptions& options,
                                         const cv::Mat& mask) {
  const cv::Mat response = HarrisResponse(grey, options);
  // A pixel is a local maximum when it equals the maximum of its nms window.
  cv::Mat dilated;
  cv::dilate(response, dilated,
             cv::getStructuringElement(cv::MORPH_RECT,
                                       cv::Size(options.nms_window_px, options.nms_window_px)));
  double max_response = 0.0;
  cv::minMaxLoc(response, nullptr, &max_response);
  const float floor =
      static_cast<float>(std::max(0.0, options.min_relative_response * max_response));
  const int border = std::max(options.border_px, 1);
  std::vector<std::vector<Keypoint>> cells(options.grid_rows * options.grid_cols);
  for (int y = border; y < response.rows - border; ++y) {
    const float* r = response.ptr<float>(y);
    const float* d = dilated.ptr<float>(y);
    const uchar* usable = mask.empty() ? nullptr : mask.ptr<uchar>(y);
    for (int x = border; x < response.cols - border; ++x) {
      if (r[x] <= floor || r[x] < d[x] || (usable && !usable[x])) continue;
      cells[RegionCell(options, response.size(), x, y)].push_back(
          {cv::Point2f(static_cast<float>(x), static_cast<float>(y)), r[x]});
    }
  }
  std::vector<Keypoint> keypoints;
  for (std::vector<Keypoint>& cell : cells) {
    const std::size_t kept = std::min<std::size_t>(cell.size(), options.per_cell);
    std::partial_sort(cell.begin(), cell.begin() + kept, cell.end(),
                      [](const Keypoint& a, const Keypoint& b) { return a.response > b.response; });
    for (std::size_t i = 0; i < kept; ++i) {
      Keypoint keypoint = cell[i];
      if (options.subpixel) {
        keypoint.position += QuadraticPeakOffset(response, static_cast<int>(keypoint.position.x),
                                                 static_cast<int>(keypoint.position.y));
      }
      keypoints.push_back(keypoint);
    }
  }
  return keypoints;
}

}  // namespace pipescope
