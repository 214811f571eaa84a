#pragma once

#include <memory>
#include <opencv2/core.hpp>

#include "pipescope/camera/camera.h"
#include "pipescope/synthetic/lighting.h"
#include "pipescope/synthetic/renderer.h"
#include "pipescope/synthetic/scale_target.h"
#include "pipescope/synthetic/scene_layouts.h"
#include "pipescope/synthetic/simulation_config.h"
#include "pipescope/synthetic/trajectory_generator.h"
#include "pipescope/synthetic/wall_texture.h"

namespace pipescope {

// Everything a configuration describes, assembled: camera, layout, wall, lights, renderer and
// motion. The dataset writer and the tests render through it.
class Simulation {
 public:
  explicit Simulation(const SimulationConfig& config);  // validates the config
  // The renderer holds references to the members: a copy or move would leave them dangling.
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  // Linear radiance of frame `index` (averaged over the exposure when motion blur is on).
  cv::Mat RenderFrameRadiance(int index) const;
  // Linear radiance of white card `index` of config.white_card_count: a uniform white wall seen
  // from a nominal pose along the route (000 §3.2), with the wall's specular finish or matte
  // (config.white_card_finish).
  cv::Mat RenderWhiteCardRadiance(int index) const;
  // world_from_cam of frame `index`.
  Eigen::Isometry3d FramePose(int index) const;

  const SimulationConfig& config() const { return config_; }
  const Camera& camera() const { return camera_; }
  const Layout& layout() const { return layout_; }
  // The wall's albedo pattern: the ground truth of an unrolled map of the wall.
  const WallTexture& texture() const { return texture_; }
  const Renderer& renderer() const { return *renderer_; }
  const TrajectoryGenerator& motion() const { return *motion_; }
  // The circle-grid target of layout scale-target (000 §3.3), null for other layouts.
  const ScaleTarget* scale_target() const { return scale_target_ ? &*scale_target_ : nullptr; }

 private:
  SimulationConfig config_;
  Camera camera_;
  Layout layout_;
  WallTexture texture_;
  Lighting lighting_;
  std::unique_ptr<Renderer> renderer_;
  std::unique_ptr<TrajectoryGenerator> motion_;
  std::optional<ScaleTarget> scale_target_;
};

}  // namespace pipescope
