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

// Wall points to shade at once, in the camera frame, as a structure of arrays (the renderer
// fills one per image row). Resize() pads the arrays to a whole number of SIMD lanes with a
// harmless point; Shade() writes only the first `size()` results.
class ShadingBatch {
 public:
  static constexpr int kLanes = 4;

  void Resize(int size);
  int size() const { return size_; }
  // Point i: position, unit normal (facing the camera side), diffuse albedo, specular
  // reflectance.
  void Set(int i, const float position[3], const float normal[3], float albedo, float specularity) {
    x_[i] = position[0];
    y_[i] = position[1];
    z_[i] = position[2];
    nx_[i] = normal[0];
    ny_[i] = normal[1];
    nz_[i] = normal[2];
    albedo_[i] = albedo;
    specularity_[i] = specularity;
  }

 private:
  friend class Lighting;
  int size_ = 0;
  std::vector<float> x_, y_, z_, nx_, ny_, nz_, albedo_, specularity_;
};

class Lighting {
 public:
  explicit Lighting(const LightingOptions& options);

  // Radiance towards the camera centre from the wall point `point_cam` with unit normal
  // `normal_cam` (facing the camera side), diffuse albedo and specular reflectance. In double:
  // the reference the renderer's Shade() is tested against.
  double Radiance(const Eigen::Vector3d& point_cam, const Eigen::Vector3d& normal_cam,
                  double albedo, double specularity) const;

  // The same model for every point of `batch`, in single precision and four points a SIMD
  // register where the CPU has SSE2 (every x86-64): the renderer's hot loop. Agrees with
  // Radiance() to float rounding, and gives the same bits with or without SIMD
  // (PIPESCOPE_LIGHTING_SCALAR in the environment at construction forces the scalar path).
  void Shade(const ShadingBatch& batch, float* radiance) const;

  const std::vector<Led>& leds() const { return leds_; }

 private:
  LightingOptions options_;
  std::vector<Led> leds_;
  double specular_normalisation_;
  double specular_cutoff_;  // below this n.h the highlight is under 1e-6 of its peak
  // Exponents that are whole numbers (the usual ones) are raised by squaring; -1 when not.
  int beam_power_;
  int specular_power_;
  bool use_simd_;  // false with PIPESCOPE_LIGHTING_SCALAR set at construction (tests)
  // Single-precision copies for Shade(), LED k's components at [k].
  std::vector<float> led_x_, led_y_, led_z_, beam_x_, beam_y_, beam_z_;
};

}  // namespace pipescope
