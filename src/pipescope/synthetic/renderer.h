#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <opencv2/core.hpp>
#include <vector>

#include "pipescope/camera/camera.h"
#include "pipescope/synthetic/lighting.h"
#include "pipescope/synthetic/scale_target.h"
#include "pipescope/synthetic/scene.h"
#include "pipescope/synthetic/wall_texture.h"

namespace pipescope {

struct RenderSettings {
  // When set (>= 0), the wall is a uniform card of this albedo instead of its texture: the
  // white-card images of 000 §3.2.
  float uniform_albedo = -1.0f;
  // The card's specular reflectance (before specular_strength); 0 is a matte card.
  float uniform_specularity = 0.0f;
  double specular_strength = 1.0;  // scales the texture's (or the card's) specularity
  // When set, this reference-scale target (000 §3.3) is painted over the textured wall.
  const ScaleTarget* scale_target = nullptr;
};

// Ray-casts the scene through the project's own camera model: each pixel's bearing comes from
// Camera::Unproject, so the simulator exercises the models it tests the estimators with. One ray
// per pixel; the texture is filtered to the pixel's footprint on the wall instead of
// supersampling.
class Renderer {
 public:
  // Pixels whose bearing lies more than `max_view_angle` from the optical axis are outside the
  // lens's image circle and stay black (a 190-degree fisheye's corners); by default the model's
  // own limit.
  Renderer(const Camera& camera, const Scene& scene, const WallTexture& texture,
           const Lighting& lighting, double max_view_angle = M_PI);

  // Linear radiance (CV_32F, camera size) seen from `world_from_cam`. Pixels outside the lens's
  // field of view and rays that leave through an open end of the network are 0. Uses all cores;
  // the result does not depend on the thread count.
  cv::Mat RenderRadiance(const Eigen::Isometry3d& world_from_cam,
                         const RenderSettings& settings = {}) const;

  const Camera& camera() const { return camera_; }

 private:
  void RenderRows(const Eigen::Isometry3d& world_from_cam, const RenderSettings& settings,
                  int row_begin, int row_end, cv::Mat* radiance) const;

  const Camera& camera_;
  const Scene& scene_;
  const WallTexture& texture_;
  const Lighting& lighting_;
  std::vector<Eigen::Vector3d> bearings_;  // per pixel, row-major; zero where invalid
  std::vector<float> pixel_angle_;         // angular size of each pixel, radians
};

}  // namespace pipescope
