#pragma once

#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <string>

namespace pipescope {

// How the camera sits in the pipe, which turns image motion into motion in the pipe frame (000
// eq. 18-19, 003 eq. 8-9). The camera looks at the wall at phi = 90 degrees (towards world +Y,
// the pipe's floor in the simulator); `axis_along_pipe` names the camera axis that points down
// the pipe (+Z): "x" for 000's wall-looking cameras (image x runs along the pipe, eq. 19), or
// "-x", "y", "-y".
struct CameraMount {
  std::string axis_along_pipe = "x";
};

// The starting pose world_from_cam: the mount's orientation, the camera on the line from the
// axis to the wall it faces, `wall_distance_m` from the wall of a pipe of `radius_m` (both 0:
// at the origin). Throws InputError naming `axis_along_pipe` for an unknown axis.
Eigen::Isometry3d MountedStartPose(const CameraMount& mount, double radius_m,
                                   double wall_distance_m);

// Integrates one pair's image motion into the camera pose (000 eq. 18-19, generalised to the
// rotation of 003 eq. 7-9). The image motion maps a reference pixel x to
// R(rotation) (x - c) + c + shift (dense/phase_correlation.h), c = `rotation_centre`. For a
// camera facing a plane at the distance where one metre spans `zeta_px_per_m` pixels, with the
// principal point `principal_point`, the camera turned by -rotation about its optical axis and
// moved parallel to the image plane by
//   delta = -R(-rotation) (shift + (R(rotation) - I)(p - c)) / zeta
// in its own frame (with rotation 0: delta = -shift / zeta, eq. 19's sign for content moving
// against the camera).
Eigen::Isometry3d ApplyImageMotion(const Eigen::Isometry3d& world_from_cam, cv::Point2d shift,
                                   double rotation_rad, double zeta_px_per_m,
                                   cv::Point2d principal_point, cv::Point2d rotation_centre);

}  // namespace pipescope
