#include "pipescope/synthetic/lighting.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <random>
#include <vector>

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

// The renderer's batch path against the double reference, over random wall points around a
// ring of LEDs (shiny and matte, whole and fractional exponents, lit and unlit), and its SIMD
// path against its scalar one bit for bit.
TEST(Lighting, ShadeMatchesRadianceAndIsTheSameWithoutSimd) {
  for (const double beam_exponent : {2.0, 1.5}) {
    LightingOptions options;
    options.led_count = 5;  // not a whole number of SIMD lanes
    options.ring_radius_m = 0.03;
    options.beam_exponent = beam_exponent;
    options.specular_exponent = beam_exponent == 2.0 ? 80.0 : 30.5;
    const Lighting lighting(options);
    setenv("PIPESCOPE_LIGHTING_SCALAR", "1", 1);
    const Lighting scalar(options);
    unsetenv("PIPESCOPE_LIGHTING_SCALAR");
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    constexpr int kPoints = 1003;  // nor is this
    ShadingBatch batch;
    batch.Resize(kPoints);
    std::vector<Eigen::Vector3d> points, normals;
    std::vector<double> albedos, specularities;
    for (int i = 0; i < kPoints; ++i) {
      // Points ahead of the lens on a wall facing roughly back at it, some facing away.
      const Eigen::Vector3d point(0.1 * unit(rng), 0.1 * unit(rng), 0.15 + 0.1 * unit(rng));
      const Eigen::Vector3d normal =
          (i % 7 == 0 ? -1.0 : 1.0) *  // every seventh faces away
          (-point.normalized() + 0.6 * Eigen::Vector3d(unit(rng), unit(rng), unit(rng)))
              .normalized();
      const double albedo = 0.5 + 0.5 * unit(rng);
      const double specularity = i % 3 == 0 ? 0.0 : 0.5 + 0.5 * unit(rng);
      const float p[3] = {static_cast<float>(point.x()), static_cast<float>(point.y()),
                          static_cast<float>(point.z())};
      const float n[3] = {static_cast<float>(normal.x()), static_cast<float>(normal.y()),
                          static_cast<float>(normal.z())};
      batch.Set(i, p, n, static_cast<float>(albedo), static_cast<float>(specularity));
      // The reference sees the same float-rounded inputs.
      points.emplace_back(p[0], p[1], p[2]);
      normals.emplace_back(n[0], n[1], n[2]);
      albedos.push_back(static_cast<float>(albedo));
      specularities.push_back(static_cast<float>(specularity));
    }
    std::vector<float> fast(kPoints), slow(kPoints);
    lighting.Shade(batch, fast.data());
    scalar.Shade(batch, slow.data());
    int lit = 0;
    for (int i = 0; i < kPoints; ++i) {
      const double expected =
          lighting.Radiance(points[i], normals[i], albedos[i], specularities[i]);
      EXPECT_NEAR(fast[i], expected, 1e-5 * expected + 1e-30) << i;
      EXPECT_EQ(std::memcmp(&fast[i], &slow[i], sizeof(float)), 0) << i;
      lit += expected > 0;
    }
    EXPECT_GT(lit, kPoints / 2);
    EXPECT_LT(lit, kPoints);  // some face away from every LED
  }
}

}  // namespace
}  // namespace pipescope
