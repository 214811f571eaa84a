#include "pipescope/feature/sparse_features.h"

#include <algorithm>
#include <opencv2/imgproc.hpp>

#include "pipescope/image/undistortion.h"

namespace pipescope {

RegionHarrisOptions SparseVoRegionHarrisOptions() {
  RegionHarrisOptions options;
  options.sigma_window_px = 2.0;
  return options;
}

SparseFeatures::SparseFeatures(const Camera& camera, const SparseFeatureOptions& options)
    : camera_(camera), options_(options) {
  options_.ransac.focal_length_px = CentralFocalLengthPx(camera);
}

FrameFeatures SparseFeatures::Extract(const cv::Mat& corrected, StageTimes* times) const {
  FrameFeatures features;
  const StageClock<> harris;
  cv::Mat image = corrected;
  if (options_.blur_sigma_px > 0.0) {
    cv::GaussianBlur(corrected, image, cv::Size(), options_.blur_sigma_px);
  }
  features.keypoints = DetectRegionHarris(image, options_.harris);
  harris.AddTo(times, "features_harris");
  const StageClock<> sift;
  features.descriptors = DescribeWithSift(image, features.keypoints, options_.sift);
  sift.AddTo(times, "features_sift");
  features.bearings.resize(features.keypoints.size());
  features.has_bearing.resize(features.keypoints.size());
  for (std::size_t i = 0; i < features.keypoints.size(); ++i) {
    const cv::Point2f& p = features.keypoints[i].position;
    features.has_bearing[i] = camera_.Unproject(Eigen::Vector2d(p.x, p.y), &features.bearings[i]);
  }
  return features;
}

PairMatches SparseFeatures::Match(const FrameFeatures& key, const FrameFeatures& frame,
                                  StageTimes* times) const {
  const StageClock<> matching;
  PairMatches result;
  std::vector<IndexMatch> candidates;
  for (const IndexMatch& match :
       MatchDescriptors(key.descriptors, frame.descriptors, options_.matching)) {
    if (key.has_bearing[match.first] && frame.has_bearing[match.second]) {
      candidates.push_back(match);
    }
  }
  result.matched = static_cast<int>(candidates.size());
  std::vector<Eigen::Vector3d> first, second;
  for (const IndexMatch& match : candidates) {
    first.push_back(key.bearings[match.first]);
    second.push_back(frame.bearings[match.second]);
  }
  matching.AddTo(times, "matching");
  const StageClock<> ransac;
  std::vector<bool> inlier;
  FivePointRansacInliers(first, second, options_.ransac, &inlier);
  std::vector<cv::Point2f> from, to;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    if (!inlier[i]) continue;
    result.inliers.push_back(candidates[i]);
    from.push_back(key.keypoints[candidates[i].first].position);
    to.push_back(frame.keypoints[candidates[i].second].position);
  }
  result.median_flow_px = MedianFlow(from, to);
  ransac.AddTo(times, "ransac");
  return result;
}

bool SparseFeatures::EndsSpan(const PairMatches& matches, int span_start_inliers) const {
  return EndsKeyFrameSpan(static_cast<int>(matches.inliers.size()), span_start_inliers,
                          matches.median_flow_px, std::max(camera_.Width(), camera_.Height()),
                          options_.key_frames);
}

}  // namespace pipescope
