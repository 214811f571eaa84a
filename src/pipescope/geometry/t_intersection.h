#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>

#include "pipescope/geometry/pipe_cylinder.h"

namespace pipescope {

// The two-cylinder T-intersection model of 001 §III-D (eq. 7-8, Fig. 4b). Two straight
// cylinders of one radius, the red one fitted relative to camera pose P_r and the blue one
// relative to P_b (each parameterised as eq. 4, 4 DOF), meet at one point I. Five parameters
// Phi = (zeta_r, l_r, zeta_b, l_b, phi) fix the change of pose between P_b and P_r:
// zeta_r, zeta_b turn about each cylinder's own axis, l_r, l_b place I on each axis (I is at
// z = l along the axis from the cylinder's origin O(C), each camera's foot on its axis: the
// distances 001 names, signed by the axis's direction), and phi in [0, 180) degrees is the angle
// between the two axes.
//
// Eq. 7 as printed composes its two factors so that I lands on the blue cylinder's origin,
// which leaves l_r and l_b redundant (only their sum acts). We keep the parameters' stated
// meaning instead: in the red cylinder's frame I = (0, 0, l_r), in the blue one's
// I = (0, 0, l_b), and
//
//   D = red_cylinder_from_blue_cylinder
//     = [I | (0, 0, l_r)] R_Z(zeta_r) R_Y(phi) R_Z(zeta_b) [I | -(0, 0, l_b)],
//
// then (eq. 8) Q = inv(C_r) D C_b, the red camera from the blue camera.
enum TIntersectionParameter { kZetaRed = 0, kLengthRed, kZetaBlue, kLengthBlue, kPhi };
constexpr int kTIntersectionParameters = 5;

// D above, for any scalar (Ceres Jets included).
template <typename T>
Eigen::Transform<T, 3, Eigen::Isometry> RedCylinderFromBlueCylinder(const T* model) {
  using Vector3 = Eigen::Matrix<T, 3, 1>;
  const Eigen::Matrix<T, 3, 3> rotation = (Eigen::AngleAxis<T>(model[kZetaRed], Vector3::UnitZ()) *
                                           Eigen::AngleAxis<T>(model[kPhi], Vector3::UnitY()) *
                                           Eigen::AngleAxis<T>(model[kZetaBlue], Vector3::UnitZ()))
                                              .toRotationMatrix();
  Eigen::Transform<T, 3, Eigen::Isometry> d = Eigen::Transform<T, 3, Eigen::Isometry>::Identity();
  d.linear() = rotation;
  d.translation() =
      Vector3(T(0), T(0), model[kLengthRed]) - rotation * Vector3(T(0), T(0), model[kLengthBlue]);
  return d;
}

// C of eq. 4 as a transform, cylinder_from_camera = [R_X(gamma) R_Y(beta) | (t_X, t_Y, 0)];
// `cylinder` is {gamma, beta, t_X, t_Y}.
template <typename T>
Eigen::Transform<T, 3, Eigen::Isometry> CylinderFromCamera(const T* cylinder) {
  using Vector3 = Eigen::Matrix<T, 3, 1>;
  Eigen::Transform<T, 3, Eigen::Isometry> c = Eigen::Transform<T, 3, Eigen::Isometry>::Identity();
  c.linear() = (Eigen::AngleAxis<T>(cylinder[0], Vector3::UnitX()) *
                Eigen::AngleAxis<T>(cylinder[1], Vector3::UnitY()))
                   .toRotationMatrix();
  c.translation() = Vector3(cylinder[2], cylinder[3], T(0));
  return c;
}

// Q of eq. 8: the red camera from the blue camera, inv(C_r) D C_b.
template <typename T>
Eigen::Transform<T, 3, Eigen::Isometry> RedCameraFromBlueCamera(const T* red_cylinder,
                                                                const T* blue_cylinder,
                                                                const T* model) {
  return CylinderFromCamera(red_cylinder).inverse() * RedCylinderFromBlueCylinder(model) *
         CylinderFromCamera(blue_cylinder);
}

// A T-intersection in the world, from the model and the red camera's pose.
struct TIntersectionGeometry {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // I
  // The axes through I, each pointing from I towards its camera's side (the way the robot
  // came in for red, the way it left for blue).
  Eigen::Vector3d red_direction = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d blue_direction = Eigen::Vector3d::UnitX();
  Eigen::Isometry3d world_from_blue_camera = Eigen::Isometry3d::Identity();  // P_b from Q
};

TIntersectionGeometry TIntersectionInWorld(const Eigen::Isometry3d& world_from_red_camera,
                                           const double red_cylinder[4],
                                           const double blue_cylinder[4],
                                           const double model[kTIntersectionParameters]);

// The model nearest to two cylinders placed independently (their axes need not meet): phi,
// zeta_r and zeta_b from the relative rotation of the cylinder frames (Z-Y-Z angles), l_r and
// l_b from the closest points of the two axes. Unset when the axes are within
// `min_angle_rad` of parallel (a straight pass, not a turn: I is not defined). `gap_m`, when
// given, receives the distance between the axes at their closest points.
std::optional<Eigen::Matrix<double, kTIntersectionParameters, 1>> FitTIntersectionModel(
    const Eigen::Isometry3d& world_from_red_camera, const double red_cylinder[4],
    const Eigen::Isometry3d& world_from_blue_camera, const double blue_cylinder[4],
    double min_angle_rad, double* gap_m = nullptr);

// 001 Fig. 4c: a scene point belongs to the cylinder whose surface is nearer. `point_red` is
// in the red cylinder's frame. Returns false for red, true for blue; `distance` receives the
// signed distance from that cylinder's wall (positive outside).
bool NearerIsBlueCylinder(const Eigen::Vector3d& point_red, const double model[5], double radius_m,
                          double* distance = nullptr);

}  // namespace pipescope
