#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace pipescope {

// How an estimated trajectory is aligned to ground truth before the absolute trajectory error.
enum class Alignment { kSe3, kSim3, kNone };

// "se3" | "sim3" | "none"; throws InputError naming --align otherwise.
Alignment AlignmentFromName(const std::string& name);
std::string AlignmentName(Alignment alignment);

// target ≈ scale * rotation * source + translation.
struct SimilarityTransform {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  double scale = 1;

  Eigen::Vector3d operator()(const Eigen::Vector3d& point) const {
    return scale * (rotation * point) + translation;
  }
};

// Least-squares alignment of `source` onto `target` (same length, corresponding points) with
// Eigen::umeyama: rotation and translation for kSe3, plus scale for kSim3, identity for kNone.
// Degenerate inputs still align the points: for collinear points the rotation about the line
// is arbitrary but the points map correctly; a single point (or all points equal) gives a pure
// translation with scale 1.
SimilarityTransform AlignPositions(const std::vector<Eigen::Vector3d>& source,
                                   const std::vector<Eigen::Vector3d>& target, Alignment alignment);

}  // namespace pipescope
