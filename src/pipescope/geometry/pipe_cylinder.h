#pragma once

#include <Eigen/Core>
#include <optional>

namespace pipescope {

// Where a ray from inside the pipe (origin within the radius) leaves it through the wall: the
// distance t > 0 along `direction` with |(origin + t direction).xy| = radius_m. Unset for a ray
// along the axis, which never meets the wall.
std::optional<double> RayToWall(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                                double radius_m);

// A straight pipe's axis in some frame: a point on it and a unit direction.
struct PipeAxis {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();
};

// The axis of the straight cylinder of 001 eq. 4, C = [R_X(gamma) R_Y(beta) | (t_X, t_Y, 0)],
// in the frame of the window's first camera: the points x with (C x)_X = (C x)_Y = 0, i.e.
// point -R~^T t~ and direction R~^T e_Z. `cylinder` is {gamma, beta, t_X, t_Y}.
PipeAxis StraightCylinderAxis(const double cylinder[4]);

}  // namespace pipescope
