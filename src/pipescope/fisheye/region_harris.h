#pragma once

#include <opencv2/core.hpp>
#include <vector>

namespace pipescope {

// Region-based Harris (001 §III-A after Nister et al. [6]): the image is divided into a grid of
// regions and the strongest corners of each are kept, for a uniform distribution.
struct RegionHarrisOptions {
  int regions_x = 2;  // 001: 2 x 2 regions
  int regions_y = 2;
  int per_region = 200;  // 001: the strongest N = 200 per region
  int block_size = 7;    // Harris window (cv::cornerHarris); larger than 3 against sensor noise
  int aperture = 3;      // Sobel aperture
  double harris_k = 0.04;
  // Corners are local maxima of the response in a (2 r + 1)^2 neighbourhood.
  int nonmax_radius_px = 3;
  // Weaker than this fraction of the strongest response in the image: no corner.
  double min_response_fraction = 1e-6;
  // Corners within this distance of the image border, or outside `mask`, are dropped (the
  // 31x31 descriptor region must fit).
  int border_px = 16;
};

// `grey`: CV_32F grey levels. `mask`: CV_8U of the image size (non-zero = usable), may be empty.
// Corners sorted by region, strongest first within each.
std::vector<cv::Point2f> DetectRegionHarris(const cv::Mat& grey, const cv::Mat& mask,
                                            const RegionHarrisOptions& options = {});

}  // namespace pipescope
