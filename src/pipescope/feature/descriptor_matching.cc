#include "pipescope/feature/descriptor_matching.h"

#include <opencv2/features2d.hpp>

namespace pipescope {

std::vector<IndexMatch> MatchDescriptors(const cv::Mat& first, const cv::Mat& second,
                                         const DescriptorMatchingOptions& options) {
  std::vector<IndexMatch> matches;
  if (first.rows < 2 || second.rows < 2) return matches;
  cv::BFMatcher matcher(cv::NORM_L2);
  std::vector<std::vector<cv::DMatch>> forward;
  matcher.knnMatch(first, second, forward, 2);
  std::vector<int> backward_best;
  if (options.mutual_check) {
    std::vector<cv::DMatch> backward;
    matcher.match(second, first, backward);
    backward_best.assign(second.rows, -1);
    for (const cv::DMatch& match : backward) backward_best[match.queryIdx] = match.trainIdx;
  }
  for (const std::vector<cv::DMatch>& pair : forward) {
    if (pair.size() < 2) continue;
    if (!(pair[0].distance < options.max_ratio * pair[1].distance)) continue;
    if (options.mutual_check && backward_best[pair[0].trainIdx] != pair[0].queryIdx) continue;
    matches.push_back({pair[0].queryIdx, pair[0].trainIdx});
  }
  return matches;
}

}  // namespace pipescope
