#include "pipescope/synthetic/presets.h"

#include "pipescope/util/error.h"

namespace pipescope {
namespace {

// 000 Table 1, pipe 1: 6 m carbon steel, 153.32 mm inner diameter, dragonfly 1024x768 at
// 7.5 fps with a 70 degree lens looking at the wall (eq. 18), four 3.5 W LEDs; dataset 1 is
// 4256 frames over the 5844.4 mm between the ground-truth marks (about 1.37 mm a frame).
SimulationConfig Steel6In() {
  SimulationConfig c;
  c.preset = "steel-6in";
  c.description =
      "000 Table 1 pipe 1: 6 m steel, ID 153.32 mm, 1024x768 70 deg wall-looking, 7.5 fps, "
      "4 LEDs, 4256 frames over 5.844 m";
  c.layout = "straight";
  c.radius_m = 0.15332 / 2.0;
  c.length_m = 6.0;
  c.end_margin_m = (6.0 - 5.8444) / 2.0;
  c.material = "steel";
  c.camera_model = "pinhole-radtan";
  c.width = 1024;
  c.height = 768;
  c.fov_deg = 70.0;
  c.view = "wall";
  c.led_count = 4;
  c.led_ring_radius_m = 0.02;
  c.fps = 7.5;
  c.frames = 4256;
  c.speed_m_s = 5.8444 / (4256 / 7.5);
  c.lateral_offset_m = 0.002;
  c.roll_deg = 1.0;
  c.wobble_deg = 0.5;
  return c;
}

// 000 Table 1, pipe 2: 4 m carbon steel, 387.56 mm inner diameter, firefly 640x480 at 30 fps
// with a 25 degree lens, forward and reverse over the 3391.0 mm between the marks, 2392 frames.
SimulationConfig Steel16In() {
  SimulationConfig c = Steel6In();
  c.preset = "steel-16in";
  c.description =
      "000 Table 1 pipe 2: 4 m steel, ID 387.56 mm, 640x480 25 deg wall-looking, 30 fps, "
      "4 LEDs, forward and reverse over 3.391 m, 2392 frames";
  c.radius_m = 0.38756 / 2.0;
  c.length_m = 4.0;
  c.end_margin_m = (4.0 - 3.391) / 2.0;
  c.width = 640;
  c.height = 480;
  c.fov_deg = 25.0;
  c.led_ring_radius_m = 0.03;
  c.fps = 30.0;
  c.frames = 2392;
  c.out_and_back = true;
  // Both legs in the frame budget, with a little slack for the turnaround.
  c.speed_m_s = 1.03 * 2.0 * 3.391 / (2392 / 30.0);
  c.lateral_offset_m = 0.004;
  return c;
}

// 001: 400 mm fiberglass network, a loop of four T-intersections T1..T4 whose centre distances
// follow Table I, a forward 190 degree fisheye (eq. 1) at 1280x960, 7.5 fps, 8 LEDs, route
// start-T1-T2-T3-T4-end (dataset A, about 26 000 frames).
SimulationConfig FiberglassNetwork() {
  SimulationConfig c;
  c.preset = "fiberglass-network";
  c.description =
      "001: ID 400 mm fiberglass loop of four Ts (Table I distances), forward 190 deg "
      "fisheye-poly 1280x960, 7.5 fps, 8 LEDs, route start-T1-T2-T3-T4-end, 26000 frames";
  c.layout = "square-loop";
  c.radius_m = 0.2;
  c.length_m = 8.150;  // T1-T2, Table I
  c.end_margin_m = 0.3;
  c.turn_radius_m = 0.2;
  c.stub_m = 1.5;
  c.material = "fiberglass";
  c.joint_spacing_m = 2.0;
  c.marking_spacing_m = 1.0;
  c.camera_model = "fisheye-poly";
  c.width = 1280;
  c.height = 960;
  c.fov_deg = 190.0;
  c.view = "forward";
  c.led_count = 8;
  c.led_ring_radius_m = 0.05;
  c.led_tilt_deg = 45.0;
  c.led_beam_exponent = 1.0;
  c.fps = 7.5;
  c.frames = 26000;
  c.speed_m_s = 0.0095;
  c.lateral_offset_m = 0.01;
  c.roll_deg = 2.0;
  c.wobble_deg = 1.0;
  return c;
}

// 003: concrete culvert of 1.5 m segments, r = 150 mm, camera at the centre looking down at
// the floor (30 degrees; 150 degrees settable, as in 003 §2.2), robot moving in x, y and turning.
SimulationConfig Culvert() {
  SimulationConfig c;
  c.preset = "culvert";
  c.description =
      "003: concrete culvert, r = 150 mm, 1.5 m segments, 640x480 camera at the centre looking "
      "down (fov_deg 30, or 150), robot moving in x, y and turning";
  c.layout = "straight";
  c.radius_m = 0.15;
  c.length_m = 6.0;
  c.end_margin_m = 0.3;
  c.material = "concrete";
  c.joint_spacing_m = 1.5;
  c.marking_spacing_m = 0.0;
  c.camera_model = "pinhole-radtan";
  c.width = 640;
  c.height = 480;
  c.fov_deg = 30.0;
  c.view = "wall";
  c.led_count = 4;
  c.led_ring_radius_m = 0.03;
  c.fps = 15.0;
  c.frames = 1500;
  c.speed_m_s = 0.05;
  c.speed_variation = 0.2;
  c.stop_count = 2;
  // The robot drives on the floor: its sideways sway (003's y) rides up the curved floor, which
  // for a camera at the centre is a roll about the axis (10 degrees: 26 mm of floor either way),
  // not a shift of the camera towards the floor; bumps move it 3 mm.
  c.lateral_offset_m = 0.003;
  c.roll_deg = 10.0;
  c.wobble_deg = 0.5;
  c.heading_deg = 10.0;
  c.wobble_wavelength_m = 1.0;
  return c;
}

// 004: a hand-held-like forward pinhole camera at near-constant speed with free 6-DOF wobble
// through a tube with straight and curved sections.
SimulationConfig TubeBend() {
  SimulationConfig c;
  c.preset = "tube-bend";
  c.description =
      "004: forward 640x480 90 deg pinhole, hand-held-like 6-DOF wobble at near-constant speed "
      "through a tube, r = 100 mm, straight 1 m - 90 deg bend (R 0.5 m) - straight 1 m";
  c.layout = "bend-tube";
  c.radius_m = 0.1;
  c.length_m = 1.0;
  c.end_margin_m = 0.15;
  c.bend_radius_m = 0.5;
  c.bend_angle_deg = 90.0;
  c.material = "steel";
  c.marking_spacing_m = 0.5;
  c.camera_model = "pinhole-radtan";
  c.width = 640;
  c.height = 480;
  c.fov_deg = 90.0;
  c.view = "forward";
  c.led_count = 4;
  c.led_ring_radius_m = 0.02;
  c.fps = 15.0;
  c.frames = 700;
  c.speed_m_s = 0.05;
  c.speed_variation = 0.05;
  c.lateral_offset_m = 0.015;
  c.roll_deg = 5.0;
  c.wobble_deg = 3.0;
  c.wobble_wavelength_m = 0.3;
  return c;
}

// 000 §3.3 (Fig. 7): a card of black circles stuck to the wall of pipe 1 under its
// wall-looking camera, for `pipescope refscale`. The robot stays on the pipe axis (no offset,
// no wobble) so the distance to the wall, and with it the true reference_scale_px_per_m, holds
// for every frame; it rolls a little about the axis and moves 2 mm a frame, so the target
// wanders about the image centre. Pipe 2's set-up: --set radius_m=0.19378 --set width=640
// --set height=480 --set fov_deg=25 --set led_ring_radius_m=0.03.
SimulationConfig ScaleTargetPreset() {
  SimulationConfig c = Steel6In();
  c.preset = "scale-target";
  c.description =
      "000 §3.3: reference-scale target, 5x4 black circles at 10 mm on a white card on the "
      "wall of pipe 1 under its wall-looking camera, 5 frames on the pipe axis";
  c.layout = "scale-target";
  c.length_m = 1.0;
  c.end_margin_m = 0.45;
  c.target_cols = 5;
  c.target_rows = 4;
  c.target_spacing_m = 0.01;
  c.target_diameter_m = 0.004;
  c.frames = 5;
  c.speed_m_s = 0.002 * c.fps;
  c.speed_variation = 0.0;
  c.lateral_offset_m = 0.0;
  c.wobble_deg = 0.0;
  c.roll_deg = 2.0;
  c.wobble_wavelength_m = 0.02;  // the roll changes from frame to frame
  return c;
}

// 001 §II / issue 4: views of a 9x6 checkerboard (25 mm squares) at varied poses for
// `pipescope calibrate`, through any camera (--set camera_model=..., fov_deg, width, height);
// the 190-degree lens of 001 is --set camera_model=fisheye-poly --set fov_deg=190. Timestamps
// are one view a second.
SimulationConfig CheckerboardPreset() {
  SimulationConfig c;
  c.preset = "checkerboard";
  c.description =
      "001 §II / issue 4: 20 views of a 9x6 checkerboard, 25 mm squares, tilted up to 50 deg "
      "and covering the image to its corners, through any camera_model (1024x768 70 deg "
      "pinhole-radtan by default), for pipescope calibrate";
  c.layout = "checkerboard";
  c.board_cols = 9;
  c.board_rows = 6;
  c.board_square_m = 0.025;
  c.camera_model = "pinhole-radtan";
  c.width = 1024;
  c.height = 768;
  c.fov_deg = 70.0;
  c.fps = 1.0;
  c.frames = 20;
  return c;
}

struct PresetEntry {
  const char* name;
  SimulationConfig (*make)();
};

const PresetEntry kPresets[] = {
    {"steel-6in", Steel6In},
    {"steel-16in", Steel16In},
    {"fiberglass-network", FiberglassNetwork},
    {"culvert", Culvert},
    {"tube-bend", TubeBend},
    {"scale-target", ScaleTargetPreset},
    {"checkerboard", CheckerboardPreset},
};

}  // namespace

const std::vector<std::string>& PresetNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> result;
    for (const PresetEntry& preset : kPresets) result.push_back(preset.name);
    return result;
  }();
  return names;
}

SimulationConfig PresetConfig(const std::string& name) {
  for (const PresetEntry& preset : kPresets) {
    if (name == preset.name) return preset.make();
  }
  std::string valid;
  for (const std::string& preset : PresetNames()) valid += (valid.empty() ? "" : ", ") + preset;
  throw InputError("--preset: unknown preset '" + name + "' (valid: " + valid + ")");
}

}  // namespace pipescope
