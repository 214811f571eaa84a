#pragma once

#include <Eigen/Core>
#include <vector>

#include "pipescope/geometry/pipe_cylinder.h"

namespace pipescope {

struct CylinderScaleOptions {
  // Scale of the Cauchy loss on the distance from the wall, relative to the radius: points far
  // off the wall (mismatches, bad triangulations) lose their influence instead of biasing s.
  double cauchy_fraction = 0.05;
  int iterations = 10;
};

// The scale s that puts points known up to scale about the frame's origin (a two-view
// reconstruction with a unit baseline, in the first camera's frame) onto the pipe wall:
//
//   s = argmin_s sum_i rho( |P (s x_i - c)| - r ),   P = I - a a^T,
//
// the wall constraint of 001 eq. 6 with the axis (c, a) known in that frame. With the axis
// through the origin the unweighted minimiser is closed form, s = r sum d_i / sum d_i^2 with
// d_i = |P x_i|; with an offset axis and the Cauchy loss rho it is reached by a few iteratively
// reweighted Gauss-Newton steps from the robust start s_0 = median(r / d_i). Returns 0 when no
// point has a distance from the axis.
double ScaleFromCylinderRadius(const std::vector<Eigen::Vector3d>& points, const PipeAxis& axis,
                               double radius, const CylinderScaleOptions& options = {});

// Scale and axis together: the cylinder of radius r (eq. 4-6, 4 degrees of freedom) and the
// scale s that put the points s x_i on its wall, by Ceres with the Cauchy loss, starting from
// `axis` and ScaleFromCylinderRadius on it. Needs the points to span the pipe's circumference
// (a fisheye two-view reconstruction does): then it depends on no earlier estimate, so the
// scale cannot drift with the accumulated rotation. `axis` receives the fit. Returns 0 when
// the fit fails.
double FitScaleAndAxis(const std::vector<Eigen::Vector3d>& points, double radius, PipeAxis* axis,
                       const CylinderScaleOptions& options = {});

}  // namespace pipescope
