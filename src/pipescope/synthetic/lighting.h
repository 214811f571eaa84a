#pragma once

#include <Eigen/Core>
#include <vector>

namespace pipescope {

// One LED on the robot, in the camera frame.
struct Led {
  Eigen::Vector3d position_cam;
  Eigen::Vector3d direction_cam;  // unit beam axis
};

// The robot's own lights are the only light in a pipe (000 §3, 001 §IV). LEDs sit on a ring
// around the lens, tilted outwards, with a cos^m beam; the wall gets inverse-square fall-off and
// the incidence cosine, and shiny walls add a Blinn-Phong highlight (000 §6.2.1, Fig. 12).
struct LightingOptions {
  int led_count = 4;
  double ring_radius_m = 0.02;      // LED distance from the optical axis
  double tilt_deg = 20.0;           // beam axis tilted outwards from the optical axis
  double beam_exponent = 2.0;       // intensity ~ cos^m(angle off the beam axis)
  double intensity = 1.0;           // radiant intensity per LED on the beam axis (arbitrary units)
  double specular_exponent = 40.0;  // Blinn-Phong shininess
};

class Lighting {
 public:
  explicit Lighting(const LightingOptions& options);

  // Radiance towards the camera centre from the wall point `point_cam` with unit normal
  // `normal_cam` (facing the camera side), diffuse albedo and specular reflectance.
  double Radiance(const Eigen::Vector3d& point_cam, const Eigen::Vector3d& normal_cam,
                  double albedo, double specularity) const;

  const std::vector<Led>& leds() const { return leds_; }

 private:
  LightingOptions options_;
  std::vector<Led> leds_;
  double specular_normalisation_;
  double specular_cutoff_;  // below this n.h the highlight is under 1e-6 of its peak
};

}  // namespace pipescope
