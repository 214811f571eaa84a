#include "pipescope/synthetic/lighting.h"

#include <cmath>

namespace pipescope {
namespace {

// x^e; by squaring for whole exponents (the usual ones), since std::pow dominated the renderer's
// profile.
double Power(double x, double exponent) {
  const double rounded = std::round(exponent);
  if (rounded != exponent || rounded < 0 || rounded > 1024) return std::pow(x, exponent);
  double result = 1.0;
  for (int n = static_cast<int>(rounded); n > 0; n >>= 1, x *= x) {
    if (n & 1) result *= x;
  }
  return result;
}

}  // namespace

Lighting::Lighting(const LightingOptions& options) : options_(options) {
  const double tilt = options.tilt_deg * M_PI / 180.0;
  for (int i = 0; i < options.led_count; ++i) {
    // Start at 45 degrees so four LEDs sit at the corners of the lens, as on the 000 robots.
    const double angle = 2.0 * M_PI * (i + 0.5) / options.led_count;
    const Eigen::Vector3d radial(std::cos(angle), std::sin(angle), 0.0);
    Led led;
    led.position_cam = options.ring_radius_m * radial;
    led.direction_cam = (std::cos(tilt) * Eigen::Vector3d::UnitZ() + std::sin(tilt) * radial);
    leds_.push_back(led);
  }
  // Energy-conserving Blinn-Phong normalisation (m + 8) / (8 pi).
  specular_normalisation_ = (options.specular_exponent + 8.0) / (8.0 * M_PI);
  specular_cutoff_ =
      options.specular_exponent > 0 ? std::exp(std::log(1e-6) / options.specular_exponent) : 0.0;
}

double Lighting::Radiance(const Eigen::Vector3d& point_cam, const Eigen::Vector3d& normal_cam,
                          double albedo, double specularity) const {
  const Eigen::Vector3d to_camera = -point_cam.normalized();
  double diffuse = 0.0;
  double specular = 0.0;
  for (const Led& led : leds_) {
    Eigen::Vector3d to_led = led.position_cam - point_cam;
    const double distance_squared = to_led.squaredNorm();
    to_led /= std::sqrt(distance_squared);
    const double incidence = normal_cam.dot(to_led);
    if (incidence <= 0.0) continue;
    const double off_axis = -led.direction_cam.dot(to_led);
    if (off_axis <= 0.0) continue;
    // Irradiance: beam pattern, inverse square, incidence cosine.
    const double irradiance =
        options_.intensity * Power(off_axis, options_.beam_exponent) * incidence / distance_squared;
    diffuse += irradiance;
    if (specularity > 0.0) {
      const Eigen::Vector3d half = (to_led + to_camera).normalized();
      const double n_dot_h = normal_cam.dot(half);
      if (n_dot_h > specular_cutoff_) {
        specular += irradiance * Power(n_dot_h, options_.specular_exponent);
      }
    }
  }
  return albedo / M_PI * diffuse + specularity * specular_normalisation_ * specular;
}

}  // namespace pipescope
