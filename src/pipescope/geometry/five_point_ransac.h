#pragma once

#include <Eigen/Core>
#include <vector>

namespace pipescope {

// Outlier removal of 000 §5.1: RANSAC with the five-point algorithm (Nister) on the bearings of
// matched keypoints, through cv::findEssentialMat on normalised image coordinates (x/z, y/z)
// with an identity camera matrix. Valid for bearings in front of the camera (z > 0), which a
// wall-looking perspective camera always gives.
struct FivePointRansacOptions {
  // Inlier threshold on the Sampson distance, in pixels of a camera with focal length
  // `focal_length_px` (the threshold handed to OpenCV is threshold_px / focal_length_px).
  double threshold_px = 1.0;
  double focal_length_px = 1.0;
  double confidence = 0.999;
  // Fewer correspondences than this: no model, every match rejected.
  int min_correspondences = 8;
};

// inlier[i] tells whether correspondence i (bearings first[i] <-> second[i]) agrees with the
// best essential matrix; returns the inlier count. Bearings with z <= 0 are outliers.
int FivePointRansacInliers(const std::vector<Eigen::Vector3d>& first,
                           const std::vector<Eigen::Vector3d>& second,
                           const FivePointRansacOptions& options, std::vector<bool>* inlier);

}  // namespace pipescope
