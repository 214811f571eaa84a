#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "pipescope/io/option_table.h"

namespace pipescope {

// Every setting of a simulated dataset. Presets (presets.h) fill it from the papers' set-ups;
// `--set key=value` overrides any field through the key table below.
struct SimulationConfig {
  std::string preset;
  std::string description;  // what the preset follows, for --list-presets

  // Scene.
  // straight | square-loop | bend-tube | checkerboard (calibration views of a planar board) |
  // scale-target (a circle-grid target on the wall, 000 §3.3)
  std::string layout = "straight";
  double radius_m = 0.07666;     // inner radius
  double length_m = 6.0;         // straight pipe length, or each leg of a bend-tube
  double end_margin_m = 0.1;     // travel stops this far from an open end
  double bend_radius_m = 0.5;    // bend-tube: centreline radius of the bend
  double bend_angle_deg = 90.0;  // bend-tube
  double turn_radius_m = 0.15;   // square-loop: the robot's turning radius inside a T
  double stub_m = 1.5;           // square-loop: length of the dead-end arm beyond each T
  bool mirror_loop = false;      // square-loop: turn right at every T instead of left
  // square-loop: "A" start-T1-T2-T3-T4-end (001's dataset A); "B" start-T4-T3-T2-T1-T4-end, the
  // T1-T4 side driven twice so that loop closure has a place seen twice (issue 23).
  std::string route = "A";

  // Calibration board (layout checkerboard): inner corners and square size.
  int board_cols = 9;
  int board_rows = 6;
  double board_square_m = 0.025;

  // Reference-scale target (layout scale-target): a grid of dark circles on the wall.
  int target_cols = 5;
  int target_rows = 4;
  double target_spacing_m = 0.01;  // centre to centre
  double target_diameter_m = 0.004;

  // Wall appearance.
  std::string material = "steel";  // steel | fiberglass | concrete
  double texture_contrast = 1.0;   // 0 = uniform albedo
  double joint_spacing_m = 0.0;    // weld seams / segment joints, 0 = none
  double marking_spacing_m = 2.0;  // painted markings and lettering

  // Camera.
  std::string camera_model = "pinhole-radtan";  // pinhole-radtan | kannala-brandt | fisheye-poly
  int width = 1024;
  int height = 768;
  double fov_deg = 70.0;     // horizontal field of view (fisheye-poly: full angle of view)
  double distortion = 0.05;  // strength of the lens's distortion terms
  // wall: principal axis along the pipe's Y, down towards the wall, image x along the axis
  // (000 eq. 18; 003's camera looking at the culvert floor). forward: along the pipe (001, 004).
  std::string view = "wall";
  double mount_offset_m = 0.0;  // camera height above the body centre (towards -y)

  // Light and sensor.
  int led_count = 4;
  double led_ring_radius_m = 0.02;
  double led_tilt_deg = 20.0;
  double led_beam_exponent = 2.0;
  double specular_strength = 0.08;  // scales the material's specularity
  double specular_exponent = 80.0;
  double exposure_target = 220.0;  // grey level of the brightest white-card pixel
  double vignetting = 0.3;
  double noise_sigma = 1.0;  // read noise, grey levels
  double electrons_per_grey_level = 20.0;
  int motion_blur_samples = 1;  // > 1 renders sub-frames over the exposure time
  double exposure_time_s = 0.01;
  int white_card_count = 5;
  // wall: the white card has the wall's own finish (its material's specular sheen, in the same
  // proportion to the diffuse light), so the gain mask holds the highlight as seen from the
  // nominal pose (000 §6.2.1); matte: a Lambertian card, whose mask leaves the sheen.
  std::string white_card_finish = "wall";

  // Motion.
  double fps = 7.5;
  int frames = 4256;
  double speed_m_s = 0.0103;
  double speed_variation = 0.1;
  int stop_count = 0;
  double stop_duration_s = 2.0;
  bool out_and_back = false;
  double lateral_offset_m = 0.002;
  double roll_deg = 1.0;
  double wobble_deg = 0.5;
  double heading_deg = 0.0;
  double wobble_wavelength_m = 0.5;
  // Distance over which the offset from the axis changes; 0: wobble_wavelength_m. Longer than a
  // leg, it is the slow wander a crawler has over metres, a different excursion on each leg.
  double wander_wavelength_m = 0.0;

  std::uint64_t seed = 1;
};

// Every settable key, declared once (io/option_table.h), in the order --list-presets prints
// them: what `--set key=value` sets and simulation.yaml records. Checks that involve several keys
// are ValidateConfig's.
const OptionTable<SimulationConfig>& SimulationOptionTable();

// A settable key's name and help text.
struct ConfigKey {
  const char* name;
  const char* help;
};

// The keys' names and help, in the table's order.
const std::vector<ConfigKey>& SimulationConfigKeys();

// The value of `key` as text (as --list-presets prints it).
std::string GetConfigValue(const SimulationConfig& config, const std::string& key);

// Parses "key=value" and sets it; throws InputError naming the key (unknown key, bad value).
void SetConfigValue(SimulationConfig* config, const std::string& assignment);

// Checks ranges and choices; throws InputError naming the key at fault.
void ValidateConfig(const SimulationConfig& config);

}  // namespace pipescope
