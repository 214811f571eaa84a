#pragma once

#include <Eigen/Geometry>
#include <random>
#include <vector>

#include "pipescope/camera/camera.h"
#include "pipescope/camera/camera_models.h"
#include "pipescope/estimation/initial_position.h"

namespace pipescope {

// 000's wall-looking mount: camera x along the pipe (+Z), optical axis towards +Y.
inline Eigen::Matrix3d WallLookingRotation() {
  Eigen::Matrix3d r;
  r.col(0) = Eigen::Vector3d::UnitZ();
  r.col(1) = Eigen::Vector3d::UnitX();
  r.col(2) = Eigen::Vector3d::UnitY();
  return r;
}

inline Eigen::Isometry3d WallLookingPose(const Eigen::Vector3d& position) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = WallLookingRotation();
  pose.translation() = position;
  return pose;
}

// steel-6in's camera: 1024x768, f = 731 px, mild barrel distortion.
inline Camera SteelSixInchCamera() {
  return Camera(CameraModelId::kPinholeRadtan, 1024, 768,
                {731.2, 731.2, 511.5, 383.5, -0.065, 0.0, 0.0, 0.0, 0.0});
}

// Wall points of a pipe of radius r seen by a camera at `pose`: random pixels cast to the wall.
inline std::vector<Eigen::Vector3d> WallPointsSeenFrom(const Camera& camera,
                                                       const Eigen::Isometry3d& pose,
                                                       double radius_m, int count, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> x(20, camera.Width() - 20), y(20, camera.Height() - 20);
  std::vector<Eigen::Vector3d> points;
  while (static_cast<int>(points.size()) < count) {
    Eigen::Vector3d bearing;
    if (!camera.Unproject({x(random), y(random)}, &bearing)) continue;
    const Eigen::Vector3d o = pose.translation(), d = pose.linear() * bearing;
    const double a = d.head<2>().squaredNorm(), b = o.head<2>().dot(d.head<2>());
    const double c = o.head<2>().squaredNorm() - radius_m * radius_m;
    const double t = (-b + std::sqrt(b * b - a * c)) / a;
    points.push_back(o + t * d);
  }
  return points;
}

// The keypoints of `points` (track g = index) that project into the image from `world_from_cam`,
// with their exact pixels and bearings.
inline std::vector<KeyFrameKeypoint> ObservedKeypoints(const Camera& camera,
                                                       const Eigen::Isometry3d& world_from_cam,
                                                       const std::vector<Eigen::Vector3d>& points) {
  std::vector<KeyFrameKeypoint> keypoints;
  for (std::size_t g = 0; g < points.size(); ++g) {
    Eigen::Vector2d pixel;
    Eigen::Vector3d bearing;
    if (camera.Project(world_from_cam.inverse() * points[g], &pixel) != ProjectionStatus::kValid ||
        !camera.Unproject(pixel, &bearing)) {
      continue;
    }
    keypoints.push_back({static_cast<long long>(g), pixel, bearing});
  }
  return keypoints;
}

}  // namespace pipescope
