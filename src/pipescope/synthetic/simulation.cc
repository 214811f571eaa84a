#include "pipescope/synthetic/simulation.h"

#include <cmath>

#include "pipescope/synthetic/simulated_camera.h"

namespace pipescope {
namespace {

// Albedo of the white card of 000 §3.2.
constexpr float kWhiteCardAlbedo = 0.9f;

const SimulationConfig& Validated(const SimulationConfig& config) {
  ValidateConfig(config);
  return config;
}

WallTextureOptions TextureOptions(const SimulationConfig& config) {
  WallTextureOptions options;
  options.material = WallMaterialFromName(config.material);
  options.texture_contrast = config.texture_contrast;
  options.seed = config.seed;
  options.joint_spacing_m = config.joint_spacing_m;
  options.marking_spacing_m = config.marking_spacing_m;
  return options;
}

LightingOptions LightOptions(const SimulationConfig& config) {
  LightingOptions options;
  options.led_count = config.led_count;
  options.ring_radius_m = config.led_ring_radius_m;
  options.tilt_deg = config.led_tilt_deg;
  options.beam_exponent = config.led_beam_exponent;
  options.specular_exponent = config.specular_exponent;
  return options;
}

MotionOptions MotionOptionsFor(const SimulationConfig& config, const Layout& layout) {
  MotionOptions options;
  options.fps = config.fps;
  options.frames = config.frames;
  options.speed_m_s = config.speed_m_s;
  options.speed_variation = config.speed_variation;
  options.stop_count = config.stop_count;
  options.stop_duration_s = config.stop_duration_s;
  options.start_s_m = layout.start_s_m;
  options.travel_m = layout.travel_m;
  options.out_and_back = config.out_and_back;
  options.lateral_offset_m = config.lateral_offset_m;
  options.roll_deg = config.roll_deg;
  options.wobble_deg = config.wobble_deg;
  options.heading_deg = config.heading_deg;
  options.wobble_wavelength_m = config.wobble_wavelength_m;
  options.wander_wavelength_m = config.wander_wavelength_m;
  options.seed = config.seed;
  return options;
}

}  // namespace

Simulation::Simulation(const SimulationConfig& config)
    : config_(Validated(config)),
      camera_(MakeSimulatedCamera(config)),
      layout_(BuildLayout(config)),
      texture_(TextureOptions(config)),
      lighting_(LightOptions(config)) {
  // A fisheye of 180 degrees or more images a circle (001 Fig. 1c); fov_deg is its full angle.
  const bool circular = config.camera_model == "fisheye-poly" && config.fov_deg >= 180.0;
  const double max_view_angle = circular ? 0.5 * config.fov_deg * M_PI / 180.0 : M_PI;
  renderer_ =
      std::make_unique<Renderer>(camera_, layout_.scene, texture_, lighting_, max_view_angle);
  motion_ = std::make_unique<TrajectoryGenerator>(layout_.route, MotionOptionsFor(config, layout_),
                                                  BodyFromCam(config));
  if (config.layout == "scale-target") {
    // The target lies under the middle frame's image centre, where 000 §3.3 measures zeta.
    ScaleTargetOptions target;
    target.cols = config.target_cols;
    target.rows = config.target_rows;
    target.spacing_m = config.target_spacing_m;
    target.diameter_m = config.target_diameter_m;
    scale_target_ =
        ScaleTarget::AtOpticalAxis(target, layout_.scene, FramePose((config.frames - 1) / 2));
  }
}

Eigen::Isometry3d Simulation::FramePose(int index) const {
  return motion_->WorldFromCam(index / config_.fps);
}

cv::Mat Simulation::RenderFrameRadiance(int index) const {
  const RenderSettings settings{.specular_strength = config_.specular_strength,
                                .scale_target = scale_target()};
  const double t = index / config_.fps;
  const int samples = config_.motion_blur_samples;
  if (samples <= 1) return renderer_->RenderRadiance(motion_->WorldFromCam(t), settings);
  // Motion blur: the mean of sub-frames spread over the exposure, centred on the timestamp.
  cv::Mat sum = cv::Mat::zeros(config_.height, config_.width, CV_32F);
  for (int k = 0; k < samples; ++k) {
    const double offset = config_.exposure_time_s * (static_cast<double>(k) / (samples - 1) - 0.5);
    sum += renderer_->RenderRadiance(motion_->WorldFromCam(std::max(0.0, t + offset)), settings);
  }
  return sum / samples;
}

cv::Mat Simulation::RenderWhiteCardRadiance(int index) const {
  const double s = layout_.start_s_m + layout_.travel_m * (index + 0.5) / config_.white_card_count;
  // A card with the wall's finish reflects the LEDs' highlight as the wall does, so the mask
  // takes out the part of the sheen that stays put in the image (000 §6.2.1). Only a card whose
  // highlight is to its diffuse light as the wall's is gives a mask that divides the wall's
  // pattern flat: the uniform wall's reflectance scaled to the card's albedo. (Keeping the
  // wall's specularity under a brighter diffuse albedo left a quarter of the variation on the
  // steel presets.)
  float specularity = 0.0f;
  if (config_.white_card_finish == "wall") {
    const WallSample wall = texture_.BaseSample();
    specularity = wall.albedo > 0 ? wall.specularity * kWhiteCardAlbedo / wall.albedo : 0.0f;
  }
  const RenderSettings settings{.uniform_albedo = kWhiteCardAlbedo,
                                .uniform_specularity = specularity,
                                .specular_strength = config_.specular_strength};
  return renderer_->RenderRadiance(motion_->NominalWorldFromCam(s), settings);
}

}  // namespace pipescope
