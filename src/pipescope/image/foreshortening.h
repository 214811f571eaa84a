#pragma once

#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <vector>

#include "pipescope/image/undistortion.h"

namespace pipescope {

// The planar model of 000 eq. 19 converts every pixel of image motion with one reference scale
// zeta = f / d, d the wall's distance along the principal ray. A wall-looking camera in a pipe
// sees a concave wall (000 §6.2.3 blames its 6-inch errors on the curvature): across the pipe,
// the lines of the image away from the principal point see the wall at a smaller depth Z, and
// when the camera moves delta along the axis such a line moves f delta / Z = zeta (d / Z) delta
// pixels, more than the centre's. A translational fit over the frame takes a weighted mean of
// those rates, so the planar model overestimates the travel, by a weighting no registration
// method states exactly.
//
// The correction: resample each line along the pipe by its own factor (folded into the
// undistortion tables, so it costs nothing per frame) so that every line of the registered band
// moves at the same rate, and convert that rate exactly.

// d / Z of each of `line_count` lines of a perspective image (focal length `focal_px`, principal
// point `principal_point`) taken from `start_world_from_cam` in a pipe of `radius_m` (axis = Z)
// whose wall is `wall_distance_m` = d along the principal ray: the lines are rows when
// `lines_are_rows` (image x runs along the pipe), else columns, each taken through the
// principal point. 1 on the principal point's line, above 1 away from it.
std::vector<double> WallDepthRatios(const Eigen::Isometry3d& start_world_from_cam, double radius_m,
                                    double wall_distance_m, double focal_px,
                                    cv::Point2d principal_point, int line_count,
                                    bool lines_are_rows);

struct AxialScaleEqualisation {
  // Line factors ratio / max ratio over the band (at most 1: every line samples inside the
  // frame; outside the band lines nearer than the band's edge keep factor 1).
  LineStretch stretch;
  // After the stretch, every line of the band moves axial_ratio * zeta * travel pixels.
  double axial_ratio = 1.0;
};

// The stretch that equalises the axial image scale of the lines [first_line, first_line +
// band_lines) (the registered band, in the ratios' pixels), from WallDepthRatios' `ratios`.
AxialScaleEqualisation EqualiseAxialScale(const std::vector<double>& ratios, int first_line,
                                          int band_lines, bool lines_are_rows);

}  // namespace pipescope
