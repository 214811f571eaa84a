#include "pipescope/geometry/camera_mount.h"

#include <cmath>

#include "pipescope/util/error.h"

namespace pipescope {

Eigen::Isometry3d MountedStartPose(const CameraMount& mount, double radius_m,
                                   double wall_distance_m) {
  const Eigen::Vector3d along = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d towards_wall = Eigen::Vector3d::UnitY();
  Eigen::Matrix3d rotation;  // columns: the camera's x, y, z axes in the pipe frame
  rotation.col(2) = towards_wall;
  const std::string& axis = mount.axis_along_pipe;
  if (axis == "x" || axis == "-x") {
    rotation.col(0) = axis == "x" ? along : Eigen::Vector3d(-along);
    rotation.col(1) = rotation.col(2).cross(rotation.col(0));
  } else if (axis == "y" || axis == "-y") {
    rotation.col(1) = axis == "y" ? along : Eigen::Vector3d(-along);
    rotation.col(0) = rotation.col(1).cross(rotation.col(2));
  } else {
    throw InputError("axis_along_pipe: must be x, -x, y or -y, got '" + axis + "'");
  }
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = rotation;
  pose.translation() = (radius_m - wall_distance_m) * towards_wall;
  return pose;
}

Eigen::Isometry3d ApplyImageMotion(const Eigen::Isometry3d& world_from_cam, cv::Point2d shift,
                                   double rotation_rad, double zeta_px_per_m,
                                   cv::Point2d principal_point, cv::Point2d rotation_centre) {
  const double c = std::cos(rotation_rad), s = std::sin(rotation_rad);
  // The same motion as a rotation about the principal point: R (x - p) + p + shift_p.
  const Eigen::Vector2d offset(principal_point.x - rotation_centre.x,
                               principal_point.y - rotation_centre.y);
  const Eigen::Matrix2d image_rotation = (Eigen::Matrix2d() << c, -s, s, c).finished();
  const Eigen::Vector2d shift_p =
      Eigen::Vector2d(shift.x, shift.y) + (image_rotation - Eigen::Matrix2d::Identity()) * offset;
  const Eigen::Vector2d delta = -image_rotation.transpose() * shift_p / zeta_px_per_m;
  Eigen::Isometry3d next = world_from_cam;
  next.translation() += world_from_cam.linear() * Eigen::Vector3d(delta.x(), delta.y(), 0.0);
  next.linear() =
      world_from_cam.linear() * Eigen::AngleAxisd(-rotation_rad, Eigen::Vector3d::UnitZ()).matrix();
  return next;
}

}  // namespace pipescope
