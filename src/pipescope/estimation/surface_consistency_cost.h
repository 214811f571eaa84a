#pragma once

#include <ceres/ceres.h>

#include <Eigen/Geometry>

#include "pipescope/estimation/surface_point.h"
#include "pipescope/estimation/track_statistics.h"

namespace pipescope {

// The cost of 000 §5.3.3 for one keypoint of a key frame whose pose is refined with six degrees
// of freedom. The keypoint's bearing eta, cast from the camera at (q, C) (world_from_cam,
// quaternion q in Eigen's x, y, z, w order), meets the wall at X_hat (eq. 35-39, the positive
// root kappa of eq. 37), with surface coordinates (h_hat, rho_hat). Eq. 43-44 for its track g,
// whose n other estimates have means (h_bar, rho_bar), is
//   eps_g = n [(h_hat - h_bar)^2 + (rho_hat - rho_bar)^2] + (spread of the estimates),
// and the spread does not depend on the pose, so the residual is
//   r = sqrt(n) (h_hat - h_bar, rho_hat - rho_bar).
// The wall intersection is the closed form of geometry/RayToWall, differentiated numerically
// (central differences): one implementation of the intersection, not a second templated one.
class SurfaceConsistencyCost {
 public:
  SurfaceConsistencyCost(const Eigen::Vector3d& bearing_cam, const TrackStatistics& track,
                         double radius_m, double phi_reference_rad)
      : bearing_cam_(bearing_cam),
        mean_(track.Mean()),
        sqrt_n_(std::sqrt(track.n)),
        radius_m_(radius_m),
        phi_reference_rad_(phi_reference_rad) {}

  bool operator()(const double* rotation_xyzw, const double* position, double* residual) const {
    Eigen::Isometry3d world_from_cam = Eigen::Isometry3d::Identity();
    world_from_cam.linear() =
        Eigen::Quaterniond(rotation_xyzw[3], rotation_xyzw[0], rotation_xyzw[1], rotation_xyzw[2])
            .normalized()
            .toRotationMatrix();
    world_from_cam.translation() = Eigen::Vector3d(position[0], position[1], position[2]);
    const std::optional<Eigen::Vector3d> wall =
        WallPointOfBearing(world_from_cam, bearing_cam_, radius_m_);
    if (!wall) return false;
    const SurfacePoint point = ToSurface(*wall, radius_m_, phi_reference_rad_);
    residual[0] = sqrt_n_ * (point.h - mean_.h);
    residual[1] = sqrt_n_ * (point.rho - mean_.rho);
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Vector3d& bearing_cam,
                                     const TrackStatistics& track, double radius_m,
                                     double phi_reference_rad) {
    return new ceres::NumericDiffCostFunction<SurfaceConsistencyCost, ceres::CENTRAL, 2, 4, 3>(
        new SurfaceConsistencyCost(bearing_cam, track, radius_m, phi_reference_rad));
  }

 private:
  Eigen::Vector3d bearing_cam_;
  SurfacePoint mean_;
  double sqrt_n_;
  double radius_m_;
  double phi_reference_rad_;
};

}  // namespace pipescope
