#include "pipescope/geometry/t_intersection.h"

#include <algorithm>
#include <cmath>

namespace pipescope {

TIntersectionGeometry TIntersectionInWorld(const Eigen::Isometry3d& world_from_red_camera,
                                           const double red_cylinder[4],
                                           const double blue_cylinder[4],
                                           const double model[kTIntersectionParameters]) {
  const Eigen::Isometry3d world_from_red_cylinder =
      world_from_red_camera * CylinderFromCamera(red_cylinder).inverse();
  const Eigen::Isometry3d red_cylinder_from_blue_cylinder = RedCylinderFromBlueCylinder(model);
  TIntersectionGeometry geometry;
  geometry.centre = world_from_red_cylinder * Eigen::Vector3d(0, 0, model[kLengthRed]);
  // Each camera's foot is its cylinder's origin, at -l along the axis from I.
  const double red_sign = model[kLengthRed] > 0.0 ? -1.0 : 1.0;
  const double blue_sign = model[kLengthBlue] > 0.0 ? -1.0 : 1.0;
  geometry.red_direction = world_from_red_cylinder.linear() * Eigen::Vector3d(0, 0, red_sign);
  geometry.blue_direction = world_from_red_cylinder.linear() *
                            red_cylinder_from_blue_cylinder.linear() *
                            Eigen::Vector3d(0, 0, blue_sign);
  geometry.world_from_blue_camera =
      world_from_red_camera * RedCameraFromBlueCamera(red_cylinder, blue_cylinder, model);
  return geometry;
}

std::optional<Eigen::Matrix<double, kTIntersectionParameters, 1>> FitTIntersectionModel(
    const Eigen::Isometry3d& world_from_red_camera, const double red_cylinder[4],
    const Eigen::Isometry3d& world_from_blue_camera, const double blue_cylinder[4],
    double min_angle_rad, double* gap_m) {
  const Eigen::Isometry3d red_cylinder_from_blue_cylinder =
      CylinderFromCamera(red_cylinder) * world_from_red_camera.inverse() * world_from_blue_camera *
      CylinderFromCamera(blue_cylinder).inverse();
  const Eigen::Matrix3d& rotation = red_cylinder_from_blue_cylinder.linear();
  const double phi = std::acos(std::clamp(rotation(2, 2), -1.0, 1.0));
  if (phi < min_angle_rad || M_PI - phi < min_angle_rad) return std::nullopt;
  Eigen::Matrix<double, kTIntersectionParameters, 1> model;
  model(kPhi) = phi;
  // rotation = R_Z(zeta_r) R_Y(phi) R_Z(zeta_b): its last column is R_Z(zeta_r) (sin phi, 0,
  // cos phi), its last row (-sin phi cos zeta_b, sin phi sin zeta_b, cos phi).
  model(kZetaRed) = std::atan2(rotation(1, 2), rotation(0, 2));
  model(kZetaBlue) = std::atan2(rotation(2, 1), -rotation(2, 0));
  // The red axis is s e_Z, the blue one t + u d in the red cylinder's frame; I is where they
  // pass closest: l_r = s, l_b = u.
  const Eigen::Vector3d t = red_cylinder_from_blue_cylinder.translation();
  const Eigen::Vector3d d = rotation.col(2);
  Eigen::Matrix<double, 3, 2> lines;
  lines.col(0) = Eigen::Vector3d::UnitZ();
  lines.col(1) = -d;
  const Eigen::Vector2d lengths = (lines.transpose() * lines).ldlt().solve(lines.transpose() * t);
  model(kLengthRed) = lengths(0);
  model(kLengthBlue) = lengths(1);
  if (gap_m != nullptr) *gap_m = (lines * lengths - t).norm();
  return model;
}

bool NearerIsBlueCylinder(const Eigen::Vector3d& point_red, const double model[5], double radius_m,
                          double* distance) {
  const double red_distance = point_red.head<2>().norm() - radius_m;
  const Eigen::Vector3d point_blue = RedCylinderFromBlueCylinder(model).inverse() * point_red;
  const double blue_distance = point_blue.head<2>().norm() - radius_m;
  const bool blue = std::abs(blue_distance) < std::abs(red_distance);
  if (distance != nullptr) *distance = blue ? blue_distance : red_distance;
  return blue;
}

}  // namespace pipescope
