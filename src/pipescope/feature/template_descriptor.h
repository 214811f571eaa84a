#pragma once

#include <opencv2/core.hpp>
#include <vector>

namespace pipescope {

// 001 §III-A: 11x11 grey-level template descriptors, each interpolated from the 31x31 region
// around its feature, compared by cosine similarity (some invariance to the strong lighting
// changes between frames).
struct TemplateDescriptorOptions {
  int region_size_px = 31;
  int descriptor_size = 11;
  // Subtract each descriptor's mean before normalising, so that the cosine similarity becomes
  // the zero-mean normalised correlation. 001 compares the raw templates; on the simulated
  // low-contrast fiberglass wall the raw cosine is dominated by the mean grey level, and only a
  // third of the mutual best matches between consecutive frames were right (two thirds with the
  // mean removed; docs/fisheye_mapping.md). false gives 001's raw templates.
  bool subtract_mean = true;
};

// One row per point (CV_32F, descriptor_size^2 columns), L2-normalised so that the cosine
// similarity of two descriptors is their dot product. `grey`: CV_32F.
cv::Mat ComputeTemplateDescriptors(const cv::Mat& grey, const std::vector<cv::Point2f>& points,
                                   const TemplateDescriptorOptions& options = {});

// Cosine-similarity matching (001 §III-A).
struct CosineMatchOptions {
  // Candidates farther apart than this in the image are not compared (features move little
  // between frames; this also limits aliasing along the repetitive pipe wall).
  double max_displacement_px = 60.0;
  double min_similarity = 0.8;
  // Keep a match only when each is the other's best (mutual nearest neighbours).
  bool mutual = true;
};

struct FeatureMatch {
  int index_a;
  int index_b;
  float similarity;
};

std::vector<FeatureMatch> MatchByCosineSimilarity(const cv::Mat& descriptors_a,
                                                  const std::vector<cv::Point2f>& points_a,
                                                  const cv::Mat& descriptors_b,
                                                  const std::vector<cv::Point2f>& points_b,
                                                  const CosineMatchOptions& options = {});

}  // namespace pipescope
