#include "pipescope/feature/sparse_features.h"

#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "pipescope/feature/round_trip_flow.h"
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
  if (options_.match_refinement_window_px > 0) {
    const StageClock<> pyramid;
    const int window = options_.match_refinement_window_px;
    cv::Mat grey8 = image;  // Lucas-Kanade takes 8-bit frames; the gain correction is float
    if (image.depth() != CV_8U) image.convertTo(grey8, CV_8U);
    cv::buildOpticalFlowPyramid(grey8, features.pyramid, cv::Size(window, window), 0);
    pyramid.AddTo(times, "features_pyramid");
  }
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
  matching.AddTo(times, "matching");
  std::vector<cv::Point2f> positions;
  std::vector<Eigen::Vector3d> bearings;
  for (const IndexMatch& match : candidates) {
    positions.push_back(frame.keypoints[match.second].position);
    bearings.push_back(frame.bearings[match.second]);
  }
  const bool refine =
      options_.match_refinement_window_px > 0 && !key.pyramid.empty() && !frame.pyramid.empty();
  if (refine) {
    const StageClock<> refinement;
    Refine(key, frame, candidates, &positions, &bearings);
    refinement.AddTo(times, "match_refinement");
  }
  const StageClock<> ransac;
  std::vector<Eigen::Vector3d> first;
  for (const IndexMatch& match : candidates) first.push_back(key.bearings[match.first]);
  std::vector<bool> inlier;
  FivePointRansacInliers(first, bearings, options_.ransac, &inlier);
  std::vector<cv::Point2f> from, to;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    if (!inlier[i]) continue;
    result.inliers.push_back(candidates[i]);
    if (refine) {
      result.refined_positions.push_back(positions[i]);
      result.refined_bearings.push_back(bearings[i]);
    }
    from.push_back(key.keypoints[candidates[i].first].position);
    to.push_back(positions[i]);
  }
  result.median_flow_px = MedianFlow(from, to);
  ransac.AddTo(times, "ransac");
  return result;
}

void SparseFeatures::Refine(const FrameFeatures& key, const FrameFeatures& frame,
                            const std::vector<IndexMatch>& candidates,
                            std::vector<cv::Point2f>* positions,
                            std::vector<Eigen::Vector3d>* bearings) const {
  std::vector<cv::Point2f> points;
  for (const IndexMatch& match : candidates) points.push_back(key.keypoints[match.first].position);
  const RoundTripFlow flow = TrackThereAndBack(key.pyramid, frame.pyramid, points,
                                               options_.match_refinement_window_px, 0, positions);
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    const cv::Point2f& moved = flow.forward[i];
    Eigen::Vector3d bearing;
    if (flow.round_trip_px[i] <= options_.match_refinement_max_round_trip_px &&
        cv::norm(moved - (*positions)[i]) <= options_.match_refinement_max_move_px &&
        camera_.Unproject(Eigen::Vector2d(moved.x, moved.y), &bearing)) {
      (*positions)[i] = moved;
      (*bearings)[i] = bearing;
    }
  }
}

void SparseFeatures::AdoptRefinedPositions(const PairMatches& matches, FrameFeatures* frame) {
  for (std::size_t i = 0; i < matches.refined_positions.size(); ++i) {
    const int index = matches.inliers[i].second;
    frame->keypoints[index].position = matches.refined_positions[i];
    frame->bearings[index] = matches.refined_bearings[i];
  }
}

bool SparseFeatures::EndsSpan(const PairMatches& matches, int span_start_inliers) const {
  return EndsKeyFrameSpan(static_cast<int>(matches.inliers.size()), span_start_inliers,
                          matches.median_flow_px, std::max(camera_.Width(), camera_.Height()),
                          options_.key_frames);
}

}  // namespace pipescope
