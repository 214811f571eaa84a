#pragma once

#include <Eigen/Geometry>
#include <cmath>

#include "pipescope/camera/camera.h"

namespace pipescope {

// The 001 lens: 190 degrees on 1280x960 (fisheye-poly, eq. 1).
inline Camera FisheyeTestCamera() {
  return Camera(CameraModelId::kFisheyePoly, 1280, 960, {290.0, -4.0, 0.0, 0.0, 639.5, 479.5});
}

// Key frame k of a synthetic straight run down a pipe along world Z: `step_m` a key frame, a
// lateral offset, a fixed tilt and a wobble about X, as cam_from_world.
inline Eigen::Isometry3d WobblingCamFromWorld(int k, double step_m) {
  Eigen::Isometry3d world_from_cam = Eigen::Isometry3d::Identity();
  world_from_cam.linear() = (Eigen::AngleAxisd(0.02 * std::sin(0.3 * k), Eigen::Vector3d::UnitX()) *
                             Eigen::AngleAxisd(0.015, Eigen::Vector3d::UnitY()))
                                .toRotationMatrix();
  world_from_cam.translation() = Eigen::Vector3d(0.01, -0.005, step_m * k);
  return world_from_cam.inverse();
}

}  // namespace pipescope
