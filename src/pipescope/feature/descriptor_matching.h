#pragma once

#include <opencv2/core.hpp>
#include <vector>

namespace pipescope {

// Descriptor matching of 000 §5.1: Lowe's ambiguity (ratio) test with a mutual-consistency
// check.
struct DescriptorMatchingOptions {
  // Best distance / second best distance must be below this (Lowe 2004: 0.8).
  double max_ratio = 0.8;
  bool mutual_check = true;
};

struct IndexMatch {
  int first = 0;   // row of the first descriptor set
  int second = 0;  // row of the second
};

// Matches rows of `first` to rows of `second` (CV_32F, L2 distance).
std::vector<IndexMatch> MatchDescriptors(const cv::Mat& first, const cv::Mat& second,
                                         const DescriptorMatchingOptions& options);

}  // namespace pipescope
