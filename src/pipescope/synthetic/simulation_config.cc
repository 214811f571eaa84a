#include "pipescope/synthetic/simulation_config.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "pipescope/util/error.h"

namespace pipescope {
namespace {

const OptionKey<SimulationConfig>& FindKey(const std::string& name) {
  for (const OptionKey<SimulationConfig>& key : SimulationOptionTable().keys()) {
    if (key.name == name) return key;
  }
  throw InputError("--set: unknown key '" + name +
                   "' (pipescope simulate --list-presets lists every key)");
}

// The shortest text of at least ten significant digits that reads back as the same double, so
// that simulation.yaml reproduces its dataset exactly.
std::string FormatDouble(double value) {
  char buffer[64];
  for (int digits = 10; digits < 17; ++digits) {
    std::snprintf(buffer, sizeof(buffer), "%.*g", digits, value);
    if (std::strtod(buffer, nullptr) == value) return buffer;
  }
  std::snprintf(buffer, sizeof(buffer), "%.17g", value);
  return buffer;
}

void Require(bool condition, const std::string& key, const std::string& what) {
  if (!condition) throw InputError("simulation key '" + key + "' " + what);
}

}  // namespace

const OptionTable<SimulationConfig>& SimulationOptionTable() {
  using C = SimulationConfig;
  static const OptionTable<C> table({
      Field<C>("layout", &C::layout,
               "straight | square-loop | bend-tube | checkerboard | scale-target"),
      Field<C>("radius_m", &C::radius_m, "pipe inner radius, m"),
      Field<C>("length_m", &C::length_m,
               "straight pipe length (bend-tube: each straight leg; square-loop: T1-T2 distance, "
               "the loop scaled alike), m"),
      Field<C>("end_margin_m", &C::end_margin_m, "travel stops this far from an open end, m"),
      Field<C>("bend_radius_m", &C::bend_radius_m, "bend-tube: centreline radius of the bend, m"),
      Field<C>("bend_angle_deg", &C::bend_angle_deg, "bend-tube: bend angle, deg"),
      Field<C>("turn_radius_m", &C::turn_radius_m,
               "square-loop: robot turning radius inside a T, m"),
      Field<C>("stub_m", &C::stub_m, "square-loop: dead-end arm beyond each T, m"),
      Field<C>("mirror_loop", &C::mirror_loop,
               "square-loop: turn right at every T instead of left (true/false)"),
      Field<C>("route", &C::route,
               "square-loop: A (start-T1-T2-T3-T4-end) or B (start-T4-T3-T2-T1-T4-end, T1-T4 "
               "driven twice)"),
      Field<C>("board_cols", &C::board_cols, "checkerboard: inner corners across"),
      Field<C>("board_rows", &C::board_rows, "checkerboard: inner corners down"),
      Field<C>("board_square_m", &C::board_square_m, "checkerboard: square size, m"),
      Field<C>("target_cols", &C::target_cols, "scale-target: circles along the pipe"),
      Field<C>("target_rows", &C::target_rows, "scale-target: circles around the pipe"),
      Field<C>("target_spacing_m", &C::target_spacing_m,
               "scale-target: centre-to-centre spacing, m"),
      Field<C>("target_diameter_m", &C::target_diameter_m, "scale-target: circle diameter, m"),
      Field<C>("material", &C::material, "steel | fiberglass | concrete"),
      Field<C>("texture_contrast", &C::texture_contrast,
               "wall texture contrast, 0 = uniform albedo"),
      Field<C>("joint_spacing_m", &C::joint_spacing_m,
               "weld seams / joints every so many m, 0 = none"),
      Field<C>("marking_spacing_m", &C::marking_spacing_m,
               "painted markings and lettering every so many m, 0 = none"),
      Field<C>("camera_model", &C::camera_model, "pinhole-radtan | kannala-brandt | fisheye-poly"),
      Field<C>("width", &C::width, "image width, px"),
      Field<C>("height", &C::height, "image height, px"),
      Field<C>("fov_deg", &C::fov_deg,
               "horizontal field of view (fisheye-poly: full angle of view), deg"),
      Field<C>("distortion", &C::distortion, "strength of the lens distortion terms"),
      Field<C>("view", &C::view, "camera mounting: wall (000 eq. 18) | forward"),
      Field<C>("mount_offset_m", &C::mount_offset_m, "camera height above the robot's centre, m"),
      Field<C>("led_count", &C::led_count, "LEDs around the lens"),
      Field<C>("led_ring_radius_m", &C::led_ring_radius_m, "LED distance from the optical axis, m"),
      Field<C>("led_tilt_deg", &C::led_tilt_deg, "LED beam tilt outwards, deg"),
      Field<C>("led_beam_exponent", &C::led_beam_exponent, "LED beam pattern cos^m"),
      Field<C>("specular_strength", &C::specular_strength,
               "scale of the wall's specular reflectance"),
      Field<C>("specular_exponent", &C::specular_exponent, "Blinn-Phong shininess"),
      Field<C>("exposure_target", &C::exposure_target,
               "grey level of the brightest white-card pixel"),
      Field<C>("vignetting", &C::vignetting, "relative fall-off at the image corner"),
      Field<C>("noise_sigma", &C::noise_sigma, "read noise, grey levels"),
      Field<C>("electrons_per_grey_level", &C::electrons_per_grey_level,
               "shot noise: variance = signal / this, 0 = none"),
      Field<C>("motion_blur_samples", &C::motion_blur_samples,
               "sub-frames per exposure, 1 = no motion blur"),
      Field<C>("exposure_time_s", &C::exposure_time_s, "exposure time for motion blur, s"),
      Field<C>("white_card_count", &C::white_card_count, "white-card renders for the gain mask"),
      Field<C>("white_card_finish", &C::white_card_finish,
               "white cards: wall (the wall's own specular sheen, in the gain mask) | matte"),
      Field<C>("fps", &C::fps, "frame rate, 1/s"),
      Field<C>("frames", &C::frames, "number of frames"),
      Field<C>("speed_m_s", &C::speed_m_s, "mean driving speed, m/s"),
      Field<C>("speed_variation", &C::speed_variation, "relative amplitude of speed changes"),
      Field<C>("stop_count", &C::stop_count, "stops during the run"),
      Field<C>("stop_duration_s", &C::stop_duration_s, "length of each stop, s"),
      Field<C>("out_and_back", &C::out_and_back, "drive to the far end and back (true/false)"),
      Field<C>("lateral_offset_m", &C::lateral_offset_m,
               "amplitude of the offset from the pipe axis, m"),
      Field<C>("roll_deg", &C::roll_deg, "amplitude of roll about the pipe axis, deg"),
      Field<C>("wobble_deg", &C::wobble_deg, "amplitude of pitch and yaw wobble, deg"),
      Field<C>("heading_deg", &C::heading_deg, "amplitude of slow turning (yaw), deg"),
      Field<C>("wobble_wavelength_m", &C::wobble_wavelength_m,
               "distance over which offsets and wobble change, m"),
      Field<C>("wander_wavelength_m", &C::wander_wavelength_m,
               "distance over which the offset from the axis changes, m (0: wobble's)"),
      Field<C>("seed", &C::seed, "random seed for texture and motion"),
  });
  return table;
}

const std::vector<ConfigKey>& SimulationConfigKeys() {
  static const std::vector<ConfigKey> keys = [] {
    std::vector<ConfigKey> result;
    for (const OptionKey<SimulationConfig>& key : SimulationOptionTable().keys()) {
      result.push_back({key.name.c_str(), key.help.c_str()});
    }
    return result;
  }();
  return keys;
}

std::string GetConfigValue(const SimulationConfig& config, const std::string& key) {
  const nlohmann::json value = FindKey(key).get(config);
  if (value.is_string()) return value.get<std::string>();
  if (value.is_number_float()) return FormatDouble(value.get<double>());
  return value.dump();  // integers, true and false
}

void SetConfigValue(SimulationConfig* config, const std::string& assignment) {
  const std::size_t equals = assignment.find('=');
  if (equals == std::string::npos || equals == 0) {
    throw InputError("--set " + assignment + ": expected key=value");
  }
  const std::string key = assignment.substr(0, equals);
  // The text as one scalar, read like a --config value (not parsed as YAML).
  FindKey(key).set(YAML::Node(assignment.substr(equals + 1)),
                   "--set " + assignment + ": key '" + key + "'", config);
}

void ValidateConfig(const SimulationConfig& c) {
  Require(c.fps > 0, "fps", "must be positive");  // first: later checks divide by it
  auto one_of = [](const std::string& value, std::initializer_list<const char*> choices) {
    return std::any_of(choices.begin(), choices.end(),
                       [&value](const char* choice) { return value == choice; });
  };
  Require(
      one_of(c.layout, {"straight", "square-loop", "bend-tube", "checkerboard", "scale-target"}),
      "layout", "must be straight, square-loop, bend-tube, checkerboard or scale-target");
  Require(c.board_cols >= 2 && c.board_rows >= 2, "board_cols",
          "and board_rows must be at least 2");
  Require(c.board_square_m > 0, "board_square_m", "must be positive");
  Require(c.target_cols >= 2 && c.target_rows >= 2, "target_cols",
          "and target_rows must be at least 2");
  Require(c.target_spacing_m > c.target_diameter_m && c.target_diameter_m > 0, "target_spacing_m",
          "must exceed target_diameter_m > 0");
  Require(one_of(c.material, {"steel", "fiberglass", "concrete"}), "material",
          "must be steel, fiberglass or concrete");
  Require(one_of(c.camera_model, {"pinhole-radtan", "kannala-brandt", "fisheye-poly"}),
          "camera_model", "must be pinhole-radtan, kannala-brandt or fisheye-poly");
  Require(one_of(c.view, {"wall", "forward"}), "view", "must be wall or forward");
  Require(c.radius_m > 0 && std::isfinite(c.radius_m), "radius_m", "must be positive");
  Require(c.length_m > 2 * c.end_margin_m, "length_m", "must exceed twice end_margin_m");
  Require(c.end_margin_m >= 0, "end_margin_m", "must not be negative");
  if (c.layout == "scale-target") {
    // The target is placed where the optical axis meets the wall (000 §3.3).
    Require(c.view == "wall", "view", "must be wall for layout scale-target");
  }
  if (c.layout == "bend-tube") {
    Require(c.bend_radius_m > c.radius_m, "bend_radius_m", "must exceed radius_m");
    Require(c.bend_angle_deg > 0 && c.bend_angle_deg <= 180, "bend_angle_deg",
            "must be in (0, 180]");
  }
  if (c.layout == "square-loop") {
    Require(c.turn_radius_m > 0 && c.turn_radius_m <= c.radius_m * 1.5, "turn_radius_m",
            "must be positive and at most 1.5 radius_m");
    Require(c.stub_m > c.radius_m + c.end_margin_m, "stub_m",
            "must exceed radius_m + end_margin_m");
    Require(one_of(c.route, {"A", "B"}), "route", "must be A or B");
  }
  Require(c.texture_contrast >= 0, "texture_contrast", "must not be negative");
  Require(c.joint_spacing_m >= 0, "joint_spacing_m", "must not be negative");
  Require(c.marking_spacing_m >= 0, "marking_spacing_m", "must not be negative");
  Require(c.width >= 16 && c.width <= 8192, "width", "must be in [16, 8192]");
  Require(c.height >= 16 && c.height <= 8192, "height", "must be in [16, 8192]");
  const double max_fov = c.camera_model == "fisheye-poly" ? 240.0 : 170.0;
  Require(c.fov_deg > 1 && c.fov_deg < max_fov, "fov_deg",
          "must be in (1, " + FormatDouble(max_fov) + ") for " + c.camera_model);
  // Beyond 4/27 a pinhole-radtan corner pixel has no pre-image (k1 = -distortion / r_corner^2).
  Require(c.distortion >= 0 && c.distortion <= 0.14, "distortion", "must be in [0, 0.14]");
  Require(c.led_count >= 1 && c.led_count <= 64, "led_count", "must be in [1, 64]");
  Require(c.led_ring_radius_m >= 0 && c.led_ring_radius_m < c.radius_m, "led_ring_radius_m",
          "must be in [0, radius_m)");
  Require(c.led_beam_exponent >= 0, "led_beam_exponent", "must not be negative");
  Require(c.specular_strength >= 0, "specular_strength", "must not be negative");
  Require(c.exposure_target > 0 && c.exposure_target <= 255, "exposure_target",
          "must be in (0, 255]");
  Require(c.vignetting >= 0 && c.vignetting < 1, "vignetting", "must be in [0, 1)");
  Require(c.noise_sigma >= 0, "noise_sigma", "must not be negative");
  Require(c.electrons_per_grey_level >= 0, "electrons_per_grey_level", "must not be negative");
  Require(c.motion_blur_samples >= 1 && c.motion_blur_samples <= 64, "motion_blur_samples",
          "must be in [1, 64]");
  Require(c.exposure_time_s >= 0 && c.exposure_time_s * c.fps <= 1.0, "exposure_time_s",
          "must be in [0, 1 / fps]");
  Require(c.white_card_count >= 1 && c.white_card_count <= 100, "white_card_count",
          "must be in [1, 100]");
  Require(one_of(c.white_card_finish, {"wall", "matte"}), "white_card_finish",
          "must be wall or matte");
  Require(c.frames >= 1 && c.frames <= 10000000, "frames", "must be in [1, 10000000]");
  Require(c.speed_m_s >= 0, "speed_m_s", "must not be negative");
  Require(c.speed_variation >= 0 && c.speed_variation < 1, "speed_variation", "must be in [0, 1)");
  Require(c.stop_count >= 0, "stop_count", "must not be negative");
  Require(c.stop_duration_s >= 0, "stop_duration_s", "must not be negative");
  Require(c.lateral_offset_m >= 0 && c.lateral_offset_m < 0.5 * c.radius_m, "lateral_offset_m",
          "must be in [0, radius_m / 2)");
  // The camera must stay well inside the pipe however the robot sways.
  Require(std::abs(c.mount_offset_m) + std::sqrt(2.0) * c.lateral_offset_m < 0.8 * c.radius_m,
          "mount_offset_m", "plus the lateral sway must keep the camera inside 0.8 radius_m");
  Require(c.wobble_wavelength_m > 0, "wobble_wavelength_m", "must be positive");
  Require(c.wander_wavelength_m >= 0, "wander_wavelength_m", "must not be negative");
}

}  // namespace pipescope
