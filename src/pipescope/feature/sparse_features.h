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
  // Each descriptor match is moved to where Lucas-Kanade takes the key frame's patch around its
  // keypoint, starting at the matched keypoint, on the full-resolution image (beyond 000, whose
  // correspondences are the two frames' own Harris positions). Against the truth, on the 6-inch
  // set-up's frames the matches erred a median 0.5-0.9 px (on the sheen 35-45 % beyond 1 px)
  // and the refined ones 0.05-0.2 px (bench/sparse_track_truth.py, docs/sparse_vo.md). The
  // window (px); 0: the keypoints' own positions.
  int match_refinement_window_px = 21;
  // A refinement whose way back misses the key frame's keypoint by more than this (px), or that
  // would move the match farther than match_refinement_max_move_px, is not taken: the match
  // keeps its keypoint's position (on faint, noisy walls most refinements fail so).
  double match_refinement_max_round_trip_px = 0.5;
  double match_refinement_max_move_px = 3.0;
};

// Keypoints of one frame (000 §5.1): positions in the distorted image, SIFT descriptors, bearings.
struct FrameFeatures {
  std::vector<Keypoint> keypoints;
  cv::Mat descriptors;
  std::vector<Eigen::Vector3d> bearings;
  std::vector<bool> has_bearing;
  // The frame's Lucas-Kanade level with its derivatives (cv::buildOpticalFlowPyramid), for the
  // refinement; empty when it is off or once the frame no longer needs it.
  std::vector<cv::Mat> pyramid;
};

struct PairMatches {
  std::vector<IndexMatch> inliers;  // key frame keypoint -> frame keypoint
  // Per inlier, where the refinement put the frame's keypoint and its bearing; empty when the
  // matches were not refined (SparseFeatures::AdoptRefinedPositions moves the keypoints there).
  std::vector<cv::Point2f> refined_positions;
  std::vector<Eigen::Vector3d> refined_bearings;
  int matched = 0;
  double median_flow_px = 0.0;
};

// The sparse front end of 000 §5.1-5.2: region Harris keypoints with SIFT descriptors and their
// bearings through the camera model, matches between two frames by descriptor with five-point
// RANSAC on the bearings, and the key-frame span test.
class SparseFeatures {
 public:
  SparseFeatures(const Camera& camera, const SparseFeatureOptions& options);

  // Thread-safe; `times` (may be null) gets the "features_harris", "features_sift" and
  // "features_pyramid" stages.
  FrameFeatures Extract(const cv::Mat& corrected, StageTimes* times) const;
  // `times` (may be null) gets the "matching", "match_refinement" and "ransac" stages. The matches
  // are refined when both frames have their pyramid
  // (SparseFeatureOptions::match_refinement_window_px).
  PairMatches Match(const FrameFeatures& key, const FrameFeatures& frame, StageTimes* times) const;
  // Moves the frame's matched keypoints to their refined positions, so that a track's later
  // observations continue from where this one was measured; nothing when not refined.
  static void AdoptRefinedPositions(const PairMatches& matches, FrameFeatures* frame);
  // Whether a frame matched to the key frame by `matches` is too far from it (000 §5.1);
  // `span_start_inliers`: the inliers of the span's first frame (0: not known).
  bool EndsSpan(const PairMatches& matches, int span_start_inliers) const;

 private:
  // Refines the candidates' frame positions and bearings in place; where the refinement fails
  // a match keeps its keypoint's position.
  void Refine(const FrameFeatures& key, const FrameFeatures& frame,
              const std::vector<IndexMatch>& candidates, std::vector<cv::Point2f>* positions,
              std::vector<Eigen::Vector3d>* bearings) const;

  const Camera& camera_;
  SparseFeatureOptions options_;
};

}  // namespace pipescope
