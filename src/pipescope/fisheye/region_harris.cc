#include "pipescope/fisheye/region_harris.h"

#include <algorithm>
#include <opencv2/imgproc.hpp>

namespace pipescope {

std::vector<cv::Point2f> DetectRegionHarris(const cv::Mat& grey, const cv::Mat& mask,
                                            const RegionHarrisOptions& options) {
  CV_Assert(grey.type() == CV_32F);
  cv::Mat response;
  cv::cornerHarris(grey, response, options.block_size, options.aperture, options.harris_k);
  cv::Mat dilated;
  const int side = 2 * options.nonmax_radius_px + 1;
  cv::dilate(response, dilated, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(side, side)));
  double max_response = 0.0;
  cv::minMaxLoc(response, nullptr, &max_response);
  const float min_response = static_cast<float>(options.min_response_fraction * max_response);

  struct Candidate {
    float response;
    cv::Point2f point;
  };
  const int regions = options.regions_x * options.regions_y;
  std::vector<std::vector<Candidate>> per_region(regions);
  const int border = options.border_px;
  for (int y = border; y < grey.rows - border; ++y) {
    const float* r = response.ptr<float>(y);
    const float* d = dilated.ptr<float>(y);
    const uchar* m = mask.empty() ? nullptr : mask.ptr<uchar>(y);
    const int region_y = y * options.regions_y / grey.rows;
    for (int x = border; x < grey.cols - border; ++x) {
      if (r[x] <= min_response || r[x] < d[x] || (m && !m[x])) continue;
      const int region = region_y * options.regions_x + x * options.regions_x / grey.cols;
      per_region[region].push_back(
          {r[x], cv::Point2f(static_cast<float>(x), static_cast<float>(y))});
    }
  }
  std::vector<cv::Point2f> corners;
  for (std::vector<Candidate>& candidates : per_region) {
    const std::size_t keep = std::min<std::size_t>(options.per_region, candidates.size());
    std::partial_sort(
        candidates.begin(), candidates.begin() + keep, candidates.end(),
        [](const Candidate& a, const Candidate& b) { return a.response > b.response; });
    for (std::size_t k = 0; k < keep; ++k) corners.push_back(candidates[k].point);
  }
  return corners;
}

}  // namespace pipescope
