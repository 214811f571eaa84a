#include "pipescope/synthetic/simulation_config.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <variant>

#include "pipescope/util/error.h"

namespace pipescope {
namespace {

using Member =
    std::variant<double SimulationConfig::*, int SimulationConfig::*, bool SimulationConfig::*,
                 std::string SimulationConfig::*, std::uint64_t SimulationConfig::*>;

struct KeyEntry {
  ConfigKey key;
  Member member;
};

const std::vector<KeyEntry>& KeyTable() {
  static const std::vector<KeyEntry> table = {
      {{"layout", "straight | square-loop | bend-tube | checkerboard | scale-target"},
       &SimulationConfig::layout},
      {{"radius_m", "pipe inner radius, m"}, &SimulationConfig::radius_m},
      {{"length_m",
        "straight pipe length (bend-tube: each straight leg; square-loop: T1-T2 distance, the "
        "loop scaled alike), m"},
       &SimulationConfig::length_m},
      {{"end_margin_m", "travel stops this far from an open end, m"},
       &SimulationConfig::end_margin_m},
      {{"bend_radius_m", "bend-tube: centreline radius of the bend, m"},
       &SimulationConfig::bend_radius_m},
      {{"bend_angle_deg", "bend-tube: bend angle, deg"}, &SimulationConfig::bend_angle_deg},
      {{"turn_radius_m", "square-loop: robot turning radius inside a T, m"},
       &SimulationConfig::turn_radius_m},
      {{"stub_m", "square-loop: dead-end arm beyond each T, m"}, &SimulationConfig::stub_m},
      {{"mirror_loop", "square-loop: turn right at every T instead of left (true/false)"},
       &SimulationConfig::mirror_loop},
      {{"board_cols", "checkerboard: inner corners across"}, &SimulationConfig::board_cols},
      {{"board_rows", "checkerboard: inner corners down"}, &SimulationConfig::board_rows},
      {{"board_square_m", "checkerboard: square size, m"}, &SimulationConfig::board_square_m},
      {{"target_cols", "scale-target: circles along the pipe"}, &SimulationConfig::target_cols},
      {{"target_rows", "scale-target: circles around the pipe"}, &SimulationConfig::target_rows},
      {{"target_spacing_m", "scale-target: centre-to-centre spacing, m"},
       &SimulationConfig::target_spacing_m},
      {{"target_diameter_m", "scale-target: circle diameter, m"},
       &SimulationConfig::target_diameter_m},
      {{"material", "steel | fiberglass | concrete"}, &SimulationConfig::material},
      {{"texture_contrast", "wall texture contrast, 0 = uniform albedo"},
       &SimulationConfig::texture_contrast},
      {{"joint_spacing_m", "weld seams / joints every so many m, 0 = none"},
       &SimulationConfig::joint_spacing_m},
      {{"marking_spacing_m", "painted markings and lettering every so many m, 0 = none"},
       &SimulationConfig::marking_spacing_m},
      {{"camera_model", "pinhole-radtan | kannala-brandt | fisheye-poly"},
       &SimulationConfig::camera_model},
      {{"width", "image width, px"}, &SimulationConfig::width},
      {{"height", "image height, px"}, &SimulationConfig::height},
      {{"fov_deg", "horizontal field of view (fisheye-poly: full angle of view), deg"},
       &SimulationConfig::fov_deg},
      {{"distortion", "strength of the lens distortion terms"}, &SimulationConfig::distortion},
      {{"view", "camera mounting: wall (000 eq. 18) | forward"}, &SimulationConfig::view},
      {{"mount_offset_m", "camera height above the robot's centre, m"},
       &SimulationConfig::mount_offset_m},
      {{"led_count", "LEDs around the lens"}, &SimulationConfig::led_count},
      {{"led_ring_radius_m", "LED distance from the optical axis, m"},
       &SimulationConfig::led_ring_radius_m},
      {{"led_tilt_deg", "LED beam tilt outwards, deg"}, &SimulationConfig::led_tilt_deg},
      {{"led_beam_exponent", "LED beam pattern cos^m"}, &SimulationConfig::led_beam_exponent},
      {{"specular_strength", "scale of the wall's specular reflectance"},
       &SimulationConfig::specular_strength},
      {{"specular_exponent", "Blinn-Phong shininess"}, &SimulationConfig::specular_exponent},
      {{"exposure_target", "grey level of the brightest white-card pixel"},
       &SimulationConfig::exposure_target},
      {{"vignetting", "relative fall-off at the image corner"}, &SimulationConfig::vignetting},
      {{"noise_sigma", "read noise, grey levels"}, &SimulationConfig::noise_sigma},
      {{"electrons_per_grey_level", "shot noise: variance = signal / this, 0 = none"},
       &SimulationConfig::electrons_per_grey_level},
      {{"motion_blur_samples", "sub-frames per exposure, 1 = no motion blur"},
       &SimulationConfig::motion_blur_samples},
      {{"exposure_time_s", "exposure time for motion blur, s"}, &SimulationConfig::exposure_time_s},
      {{"white_card_count", "white-card renders for the gain mask"},
       &SimulationConfig::white_card_count},
      {{"white_card_finish",
        "white cards: wall (the wall's own specular sheen, in the gain mask) | matte"},
       &SimulationConfig::white_card_finish},
      {{"fps", "frame rate, 1/s"}, &SimulationConfig::fps},
      {{"frames", "number of frames"}, &SimulationConfig::frames},
      {{"speed_m_s", "mean driving speed, m/s"}, &SimulationConfig::speed_m_s},
      {{"speed_variation", "relative amplitude of speed changes"},
       &SimulationConfig::speed_variation},
      {{"stop_count", "stops during the run"}, &SimulationConfig::stop_count},
      {{"stop_duration_s", "length of each stop, s"}, &SimulationConfig::stop_duration_s},
      {{"out_and_back", "drive to the far end and back (true/false)"},
       &SimulationConfig::out_and_back},
      {{"lateral_offset_m", "amplitude of the offset from the pipe axis, m"},
       &SimulationConfig::lateral_offset_m},
      {{"roll_deg", "amplitude of roll about the pipe axis, deg"}, &SimulationConfig::roll_deg},
      {{"wobble_deg", "amplitude of pitch and yaw wobble, deg"}, &SimulationConfig::wobble_deg},
      {{"heading_deg", "amplitude of slow turning (yaw), deg"}, &SimulationConfig::heading_deg},
      {{"wobble_wavelength_m", "distance over which offsets and wobble change, m"},
       &SimulationConfig::wobble_wavelength_m},
      {{"seed", "random seed for texture and motion"}, &SimulationConfig::seed},
  };
  return table;
}

const KeyEntry& FindKey(const std::string& name) {
  for (const KeyEntry& entry : KeyTable()) {
    if (name == entry.key.name) return entry;
  }
  throw InputError("--set: unknown key '" + name +
                   "' (pipescope simulate --list-presets lists every key)");
}

std::string FormatDouble(double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.10g", value);
  return buffer;
}

template <typename T>
T ParseNumber(const std::string& key, const std::string& text) {
  try {
    std::size_t used = 0;
    T value;
    if constexpr (std::is_same_v<T, double>) {
      value = std::stod(text, &used);
    } else if constexpr (std::is_same_v<T, int>) {
      value = std::stoi(text, &used);
    } else {
      if (!text.empty() && text[0] == '-') throw std::invalid_argument("negative");
      value = std::stoull(text, &used);
    }
    if (used != text.size()) throw std::invalid_argument("trailing characters");
    if constexpr (std::is_same_v<T, double>) {
      if (!std::isfinite(value)) throw std::invalid_argument("not finite");
    }
    return value;
  } catch (const std::exception&) {
    throw InputError("--set " + key + "=" + text + ": not a valid number");
  }
}

void Require(bool condition, const std::string& key, const std::string& what) {
  if (!condition) throw InputError("simulation key '" + key + "' " + what);
}

}  // namespace

const std::vector<ConfigKey>& SimulationConfigKeys() {
  static const std::vector<ConfigKey> keys = [] {
    std::vector<ConfigKey> result;
    for (const KeyEntry& entry : KeyTable()) result.push_back(entry.key);
    return result;
  }();
  return keys;
}

std::string GetConfigValue(const SimulationConfig& config, const std::string& key) {
  return std::visit(
      [&config](auto member) -> std::string {
        const auto& value = config.*member;
        using T = std::decay_t<decltype(value)>;
        if constexpr (std::is_same_v<T, double>) return FormatDouble(value);
        if constexpr (std::is_same_v<T, bool>) return value ? "true" : "false";
        if constexpr (std::is_same_v<T, std::string>) return value;
        if constexpr (std::is_same_v<T, int> || std::is_same_v<T, std::uint64_t>) {
          return std::to_string(value);
        }
      },
      FindKey(key).member);
}

void SetConfigValue(SimulationConfig* config, const std::string& assignment) {
  const std::size_t equals = assignment.find('=');
  if (equals == std::string::npos || equals == 0) {
    throw InputError("--set " + assignment + ": expected key=value");
  }
  const std::string key = assignment.substr(0, equals);
  const std::string text = assignment.substr(equals + 1);
  std::visit(
      [&](auto member) {
        auto& value = config->*member;
        using T = std::decay_t<decltype(value)>;
        if constexpr (std::is_same_v<T, std::string>) {
          value = text;
        } else if constexpr (std::is_same_v<T, bool>) {
          if (text == "true" || text == "1") {
            value = true;
          } else if (text == "false" || text == "0") {
            value = false;
          } else {
            throw InputError("--set " + key + "=" + text + ": expected true or false");
          }
        } else {
          value = ParseNumber<T>(key, text);
        }
      },
      FindKey(key).member);
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
}

}  // namespace pipescope
