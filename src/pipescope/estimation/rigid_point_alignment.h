#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace pipescope {

// The rigid motion between two sets of the same 3-D points, each in its own frame, with
// outliers among the pairs: RANSAC over three-point rigid fits (Eigen::umeyama, no scale), then
// one fit to every inlier. Loop closure (001 §III-E) aligns the map points two passes of a
// section saw at the same wall: both passes' points are metric, so no scale is estimated.
struct RigidAlignmentOptions {
  double inlier_threshold_m = 0.01;  // |T q - p| below this is an inlier
  // Also a scale s (first ~ s R second + t): where one pass's odometry lost its scale, its
  // local structure is still the wall's shape, and R and t (the second camera in the first
  // camera's frame, in the first's units) still hold.
  bool with_scale = false;
  int iterations = 500;
  unsigned long long seed = 1;
};

struct RigidAlignment {
  bool found = false;                                                   // at least three inliers
  Eigen::Isometry3d first_from_second = Eigen::Isometry3d::Identity();  // rotation, translation
  double scale = 1.0;        // of the second set against the first (1 without with_scale)
  std::vector<int> inliers;  // indices into the pairs
  double rms_m = 0.0;        // over the inliers, after the final fit
};

// Finds T with first[i] ~ T * (scale * second[i]). Throws InputError when the sizes differ.
RigidAlignment AlignPointPairs(const std::vector<Eigen::Vector3d>& first,
                               const std::vector<Eigen::Vector3d>& second,
                               const RigidAlignmentOptions& options = {});

}  // namespace pipescope
