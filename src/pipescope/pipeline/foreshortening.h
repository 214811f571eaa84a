#pragma once

#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <vector>

namespace pipescope {

// The planar model of 000 eq. 19 converts every pixel of image motion with one reference scale
// zeta = f / d, d the wall's distance along the principal ray. A wall-looking camera in a pipe
// sees a concave wall (000 §6.2.3 blames its 6-inch errors on the curvature): across the pipe,
// the lines of the image away from the principal point see the wall at a smaller depth Z, and
// when the camera moves delta along the axis such a line moves f delta / Z = zeta (d / Z) delta
// pixels, more than the centre's. The whole frame's shift is a weighted mean of zeta d / Z over
// the lines, so the planar model overestimates the travel. This profile holds d / Z for each
// line of the registered band, from the start pose and the radius, and weights it as the
// registration does: by each line's image gradient energy along the pipe (the Gauss-Newton
// normal equations of a translation weight each line so). Dividing the axial shift by the
// weighted ratio undoes the bias to first order; motion across the pipe keeps the planar model.
class ForeshorteningProfile {
 public:
  // `start_world_from_cam`: the camera's mounted pose in the pipe frame (axis = Z), `radius_m`
  // the pipe's, `wall_distance_m` = d. The band's pixels are in a perspective image of focal
  // length `focal_px` and principal point `principal_point` (the prepared frames).
  // `lines_are_rows`: image x runs along the pipe (the lines across it are rows).
  ForeshorteningProfile(const Eigen::Isometry3d& start_world_from_cam, double radius_m,
                        double wall_distance_m, double focal_px, cv::Point2d principal_point,
                        const cv::Rect& band, bool lines_are_rows);

  // d / Z of each line of the band (1 on the principal point's line, above 1 away from it).
  const std::vector<double>& ratios() const { return ratios_; }

  // The weighted mean ratio for the band `reference` (CV_32F, band-sized): the factor by which
  // the registered axial shift exceeds zeta times the travel.
  double AxialScaleRatio(const cv::Mat& reference) const;

 private:
  std::vector<double> ratios_;
  bool lines_are_rows_;
};

}  // namespace pipescope
