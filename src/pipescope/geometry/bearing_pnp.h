#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace pipescope {

// The pose of a camera from known 3-D points and the unit bearings it sees them along, with
// outliers among the pairs: OpenCV's RANSAC PnP and its Levenberg-Marquardt refinement on the
// bearings' normalised-plane coordinates (any camera model: the bearings come from its
// Unproject), inliers by the angle between bearing and predicted direction. Loop closure
// (001 §III-E) places a later pass's key frame against an earlier pass's map points this way,
// so the later pass's own scale, which its odometry may have lost, plays no part.
struct BearingPnpOptions {
  double max_angle_deg = 0.5;  // a pair farther off is an outlier
  double min_bearing_z = 0.2;  // bearings farther than 78 deg off the axis are left out
  int iterations = 500;
};

struct BearingPnp {
  bool found = false;
  Eigen::Isometry3d cam_from_points = Eigen::Isometry3d::Identity();
  std::vector<int> inliers;  // indices into the pairs
  double rms_deg = 0.0;      // angle between bearing and prediction, over the inliers
};

// Throws InputError when the sizes differ.
BearingPnp SolveBearingPnp(const std::vector<Eigen::Vector3d>& points,
                           const std::vector<Eigen::Vector3d>& bearings,
                           const BearingPnpOptions& options = {});

}  // namespace pipescope
