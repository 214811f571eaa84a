#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <utility>
#include <vector>

#include "pipescope/camera/camera.h"
#include "pipescope/feature/descriptor_matching.h"
#include "pipescope/feature/key_frame_selection.h"
#include "pipescope/feature/region_harris.h"
#include "pipescope/feature/sift_description.h"
#include "pipescope/geometry/five_point_ransac.h"
#include "pipescope/util/stage_times.h"

namespace pipescope {

// 000's region Harris with sigma_W = 2 instead of 3 (beyond 000, measured: docs/sparse_vo.md,
// steel-16in 0.731 % -> 0.095 %, steel-6in 0.068 % -> 0.016 %).
RegionHarrisOptions SparseVoRegionHarrisOptions();

struct SparseFeatureOptions {
  RegionHarrisOptions harris = SparseVoRegionHarrisOptions();
  SiftDescriptionOptions sift;
  DescriptorMatchingOptions matching;
  FivePointRansacOptions ransac;  // focal_length_px is taken from the camera
  KeyFrameOptions key_frames;
  // Sigma (px) of a Gaussian blur of the frame before detection and description; 0: none.
  double blur_sigma_px = 0.0;
};

// Keypoints of one frame (000 §5.1): positions in the distorted image, SIFT descriptors, bearings.
struct FrameFeatures {
  std::vector<Keypoint> keypoints;
  cv::Mat descriptors;
  std::vector<Eigen::Vector3d> bearings;
  std::vector<bool> has_bearing;
};

struct PairMatches {
  std::vector<IndexMatch> inliers;  // key frame keypoint -> frame keypoint
  int matched = 0;
  double median_flow_px = 0.0;
};

// The sparse front end of 000 §5.1-5.2: region Harris keypoints with SIFT descriptors and their
// bearings through the camera model, matches between two frames by descriptor with five-point
// RANSAC on the bearings, and the key-frame span test.
class SparseFeatures {
 public:
  SparseFeatures(const Camera& camera, const SparseFeatureOptions& options);

  // Thread-safe; `times` (may be null) gets the "features_harris" and "features_sift" stages.
  FrameFeatures Extract(const cv::Mat& corrected, StageTimes* times) const;
  // `times` (may be null) gets the "matching" and "ransac" stages.
  PairMatches Match(const FrameFeatures& key, const FrameFeatures& frame, StageTimes* times) const;
  // Whether a frame matched to the key frame by `matches` is too far from it (000 §5.1);
  // `span_start_inliers`: the inliers of the span's first frame (0: not known).
  bool EndsSpan(const PairMatches& matches, int span_start_inliers) const;

 private:
  const Camera& camera_;
  SparseFeatureOptions options_;
};

}  // namespace pipescope
