#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace pipescope {

// One observation of a scene point: the camera's pose and the unit bearing of the point in that
// camera's frame (the fisheye model's unprojection, 001 eq. 1).
struct BearingObservation {
  Eigen::Isometry3d cam_from_world = Eigen::Isometry3d::Identity();
  Eigen::Vector3d bearing = Eigen::Vector3d::UnitZ();
};

// The multi-view midpoint triangulation on bearings: the world point X minimising the sum of
// squared distances from the rays c_i + s b_i (c_i the camera centre, b_i the bearing rotated to
// the world frame),
//
//   X = argmin sum_i |(I - b_i b_i^T)(X - c_i)|^2,   i.e.   sum_i P_i X = sum_i P_i c_i,
//
// with P_i = I - b_i b_i^T. Unlike the reprojection error it needs no projection and holds for
// bearings beyond 90 degrees (001's fisheye sees past 180). Returns false with fewer than two
// observations, when the rays are near parallel (the normal matrix's smallest eigenvalue below
// `min_eigenvalue`, about the squared sine of the widest angle between rays), or when the point
// lies behind any of the cameras.
bool TriangulateMidpoint(const std::vector<BearingObservation>& observations,
                         Eigen::Vector3d* point, double min_eigenvalue = 1e-8);

}  // namespace pipescope
