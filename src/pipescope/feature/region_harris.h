#pragma once

#include <opencv2/core.hpp>
#include <vector>

namespace pipescope {

// The region-based Harris detector of 000 §5.1 and 001 §III-A: the image is cut into a grid of
// equal cells and the strongest corners of each cell are kept, so keypoints cover the whole frame
// (000 Fig. 9). The defaults are 000's; feature/feature_tracker.h sets 001's.
struct RegionHarrisOptions {
  int grid_rows = 6;  // 000: 6 x 8 grid; 001: 2 x 2 regions
  int grid_cols = 8;
  int per_cell = 20;                 // 000: the 20 most salient per cell; 001: 200
  int nms_window_px = 7;             // 000: 7 x 7 non-maximum suppression
  double sigma_window_px = 3.0;      // sigma_W of the integrating Gaussian (eq. 30)
  double sigma_derivative_px = 1.5;  // sigma_D of the derivative-of-Gaussian kernels (eq. 31)
  // 0: the Gaussian window and derivatives above (000). Otherwise OpenCV's cv::cornerHarris: a
  // box window of this side over Sobel derivatives of aperture `sobel_aperture` (001's tracker).
  int box_window_px = 0;
  int sobel_aperture = 3;
  double k = 0.04;  // eq. 28-29
  // Corners closer than this to the image border are dropped (the descriptor patch and the
  // quadratic fit need the neighbourhood).
  int border_px = 8;
  // Corners weaker than this fraction of the image's strongest are dropped (flat wall).
  double min_relative_response = 1e-4;
  // Sub-pixel positions from the quadratic fit (eq. 32-34); false: integer pixels.
  bool subpixel = true;
};

struct Keypoint {
  cv::Point2f position;  // sub-pixel (eq. 32-34)
  float response = 0.f;  // Harris cornerness at the integer maximum
};

// Harris cornerness det(A) - k trace(A)^2 (the usual form; 000 eq. 29 prints trace(A) without
// the square, which is not scale-consistent with eq. 28's lambda products) of `grey` (one
// channel, any depth; converted to CV_32F), with the window `options` chooses.
cv::Mat HarrisResponse(const cv::Mat& grey, const RegionHarrisOptions& options);

// The sub-pixel offset of a maximum of `response` at integer (x, y) from the quadratic Taylor
// fit of eq. 32-34: -H^-1 g with central differences. Zero when H is not negative definite or
// the offset leaves the pixel (|offset| > 1 in either axis).
cv::Point2f QuadraticPeakOffset(const cv::Mat& response, int x, int y);

// The grid cell of `options` (row-major index) that holds pixel (x, y) of an image of `size`.
int RegionCell(const RegionHarrisOptions& options, cv::Size size, int x, int y);

// The keypoints of a gain-corrected (distorted) image: per cell the strongest local maxima of
// the cornerness over a nms_window_px window, strongest first within each cell. `mask`: CV_8U of
// the image size, non-zero where corners may lie; may be empty.
std::vector<Keypoint> DetectRegionHarris(const cv::Mat& grey, const RegionHarrisOptions& options,
                                         const cv::Mat& mask = cv::Mat());

}  // namespace pipescope
