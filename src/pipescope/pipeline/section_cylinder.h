#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <vector>

#include "pipescope/estimation/keyframe_odometry.h"

namespace pipescope {

// A straight cylinder (001 eq. 4) fitted to a stretch of a mapped section's points, relative to
// one key frame's camera.
struct SectionCylinderFit {
  double cylinder[4] = {0, 0, 0, 0};  // {gamma, beta, t_X, t_Y} relative to the origin camera
  double median_distance_m = 0.0;     // of the points from the fitted wall
  int points = 0;
};

// Fits the cylinder relative to the camera `world_from_origin` to the map's points of `section`
// that lie beside the travel from that camera to `far_centre` (along it, from 0 to its length
// plus `slack_m`; none behind the origin camera, where a T may be). Unset with fewer than 20
// such points. The median distance is robust to the mismatched tracks the fit's Huber loss
// discounted.
std::optional<SectionCylinderFit> FitSectionCylinder(const std::vector<SparsePoint>& points,
                                                     int section,
                                                     const Eigen::Isometry3d& world_from_origin,
                                                     const Eigen::Vector3d& far_centre,
                                                     double radius_m, double slack_m);

// The fitted cylinder's axis in the world, pointing from the origin camera towards `far_centre`.
PipeAxis SectionCylinderAxis(const SectionCylinderFit& fit,
                             const Eigen::Isometry3d& world_from_origin,
                             const Eigen::Vector3d& far_centre);

}  // namespace pipescope
