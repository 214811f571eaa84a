#include "pipescope/feature/key_frame_selection.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "pipescope/util/median.h"

namespace pipescope {

double MedianFlow(const std::vector<cv::Point2f>& from, const std::vector<cv::Point2f>& to) {
  std::vector<double> lengths;
  for (std::size_t i = 0; i < std::min(from.size(), to.size()); ++i) {
    lengths.push_back(std::hypot(to[i].x - from[i].x, to[i].y - from[i].y));
  }
  return UpperMedian(std::move(lengths));
}

bool EndsKeyFrameSpan(int correspondences, int span_start_correspondences, double median_flow_px,
                      int image_extent_px, const KeyFrameOptions& options) {
  double minimum = options.min_correspondences;
  if (options.min_correspondence_fraction > 0 && span_start_correspondences > 0) {
    minimum = std::min(minimum, options.min_correspondence_fraction * span_start_correspondences);
  }
  return correspondences < minimum ||
         median_flow_px > options.max_median_flow_fraction * image_extent_px;
}

}  // namespace pipescope
