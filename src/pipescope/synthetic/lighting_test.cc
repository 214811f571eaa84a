#include "pipescope/synthetic/lighting.h"

#include <gtest/gtest.h>

#include <cmath>

namespace pipescope {
namespace {

LightingOptions OneLedOnAxis() {
  LightingOptions options;
  options.led_count = 1;
  options.ring_radius_m = 0.0;
  options.tilt_deg = 0.0;
  options.beam_exponent = 2.0;
  options.intensity = 3.0;
  return options;
}

TEST(Lighting, LambertianInverseSquareClosedForm) {
  const Lighting lighting(OneLedOnAxis());
  const Eigen::Vector3d normal(0, 0, -1);
  // Straight ahead: radiance = albedo / pi * I / d^2.
  EXPECT_NEAR(lighting.Radiance({0, 0, 0.1}, normal, 0.5, 0.0), 0.5 / M_PI * 3.0 / 0.01, 1e-9);
  EXPECT_NEAR(lighting.Radiance({0, 0, 0.2}, normal, 0.5, 0.0),
              lighting.Radiance({0, 0, 0.1}, normal, 0.5, 0.0) / 4.0, 1e-9);
  // Off axis by 45 degrees on a plane facing the LED: beam cos^2, incidence cos, distance^2.
  const Eigen::Vector3d point(0.1, 0, 0.1);
  const double c = std::cos(M_PI / 4.0);
  EXPECT_NEAR(lighting.Radiance(point, normal, 0.5, 0.0),
              0.5 / M_PI * 3.0 * c * c * c / point.squaredNorm(), 1e-9);
  // A wall facing away receives nothing.
  EXPECT_EQ(lighting.Radiance({0, 0, 0.1}, Eigen::Vector3d(0, 0, 1), 0.5, 0.0), 0.0);
}

TEST(Lighting, SpecularHighlightAtMirrorDirection) {
  const Lighting lighting(OneLedOnAxis());
  const Eigen::Vector3d normal(0, 0, -1);
  // LED and camera coincide, so the mirror direction is straight back along the axis: the
  // highlight peaks there and falls off away from it.
  const double on_axis = lighting.Radiance({0, 0, 0.1}, normal, 0.0, 1.0);
  const double off_axis = lighting.Radiance({0.05, 0, 0.1}, normal, 0.0, 1.0);
  EXPECT_NEAR(on_axis, (40.0 + 8.0) / (8.0 * M_PI) * 3.0 / 0.01, 1e-6);
  EXPECT_LT(off_axis, 0.2 * on_axis);
}

TEST(Lighting, RingOfLedsAroundTheLens) {
  LightingOptions options;
  options.led_count = 8;
  options.ring_radius_m = 0.05;
  options.tilt_deg = 30.0;
  const Lighting lighting(options);
  ASSERT_EQ(lighting.leds().size(), 8u);
  for (const Led& led : lighting.leds()) {
    EXPECT_NEAR(led.position_cam.norm(), 0.05, 1e-12);
    EXPECT_NEAR(led.position_cam.z(), 0.0, 1e-12);
    EXPECT_NEAR(led.direction_cam.norm(), 1.0, 1e-12);
    EXPECT_NEAR(std::acos(led.direction_cam.z()), 30.0 * M_PI / 180.0, 1e-9);
    // Tilted outwards: the beam leans the way the LED sits.
    EXPECT_GT(led.direction_cam.head<2>().dot(led.position_cam.head<2>()), 0.0);
  }
}

}  // namespace
}  // namespace pipescope
