#include "pipescope/synthetic/lighting.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#if defined(__SSE2__)
#include <emmintrin.h>
#define PIPESCOPE_LIGHTING_SSE2 1
#endif

// Shade()'s SIMD and scalar paths must round alike, so no fused multiply-adds even in builds for
// CPUs that have them (-march=native).
#if defined(__clang__)
#pragma clang fp contract(off)
#elif defined(__GNUC__)
#pragma GCC optimize("fp-contract=off")
#endif

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

// The exponent as a whole number for raising by squaring, or -1.
int WholePower(double exponent) {
  const double rounded = std::round(exponent);
  return rounded == exponent && rounded >= 0 && rounded <= 1024 ? static_cast<int>(rounded) : -1;
}

// Shade() is written once, as a template over the lane type: float for the scalar path, F4 (four
// floats in an SSE register) for the SIMD path. Both do the same IEEE operations in the same
// order, so they give the same bits.
inline float Sqrt(float x) { return std::sqrt(x); }
inline float Select(bool mask, float a, float b) { return mask ? a : b; }
inline float Broadcast(float value, float /*tag*/) { return value; }
inline float PowLanes(float x, float exponent) { return std::pow(x, exponent); }

#ifdef PIPESCOPE_LIGHTING_SSE2
struct F4 {
  __m128 v;
};
struct M4 {
  __m128 m;
};
inline F4 operator+(F4 a, F4 b) { return {_mm_add_ps(a.v, b.v)}; }
inline F4 operator-(F4 a, F4 b) { return {_mm_sub_ps(a.v, b.v)}; }
inline F4 operator*(F4 a, F4 b) { return {_mm_mul_ps(a.v, b.v)}; }
inline F4 operator/(F4 a, F4 b) { return {_mm_div_ps(a.v, b.v)}; }
inline M4 operator>(F4 a, F4 b) { return {_mm_cmpgt_ps(a.v, b.v)}; }
inline M4 operator&(M4 a, M4 b) { return {_mm_and_ps(a.m, b.m)}; }
inline F4 Sqrt(F4 x) { return {_mm_sqrt_ps(x.v)}; }
inline F4 Select(M4 mask, F4 a, F4 b) {
  return {_mm_or_ps(_mm_and_ps(mask.m, a.v), _mm_andnot_ps(mask.m, b.v))};
}
inline F4 Broadcast(float value, F4 /*tag*/) { return {_mm_set1_ps(value)}; }
inline F4 PowLanes(F4 x, float exponent) {
  alignas(16) float lanes[4];
  _mm_store_ps(lanes, x.v);
  for (float& lane : lanes) lane = std::pow(lane, exponent);
  return {_mm_load_ps(lanes)};
}
#endif

// x^n by squaring when n >= 0, else std::pow with `exponent`.
template <typename V>
V Pow(V x, int n, float exponent) {
  if (n < 0) return PowLanes(x, exponent);
  if (n == 2) return x * x;  // the usual beam, without the loop (the loop gives 1 * (x * x))
  V result = Broadcast(1.0f, x);
  for (; n > 0; n >>= 1, x = x * x) {
    if (n & 1) result = result * x;
  }
  return result;
}

struct ShadeConstants {
  int led_count;
  const float* led_x;
  const float* led_y;
  const float* led_z;
  const float* beam_x;
  const float* beam_y;
  const float* beam_z;
  float intensity;
  int beam_power;
  float beam_exponent;
  int specular_power;
  float specular_exponent;
  float specular_cutoff;
  float specular_normalisation;
};

// Radiance(), lane by lane; `shiny` false skips the highlight where no lane has one (its term is
// then 0 either way).
template <typename V>
V ShadeLanes(const ShadeConstants& c, V x, V y, V z, V nx, V ny, V nz, V albedo, V specularity,
             bool shiny) {
  const V zero = Broadcast(0.0f, x);
  const V inv_depth = Broadcast(1.0f, x) / Sqrt(x * x + y * y + z * z);
  const V to_camera_x = zero - x * inv_depth;
  const V to_camera_y = zero - y * inv_depth;
  const V to_camera_z = zero - z * inv_depth;
  const V intensity = Broadcast(c.intensity, x);
  const V cutoff = Broadcast(c.specular_cutoff, x);
  V diffuse = zero;
  V specular = zero;
  for (int k = 0; k < c.led_count; ++k) {
    const V dx = Broadcast(c.led_x[k], x) - x;
    const V dy = Broadcast(c.led_y[k], x) - y;
    const V dz = Broadcast(c.led_z[k], x) - z;
    const V distance_squared = dx * dx + dy * dy + dz * dz;
    const V inv_distance = Broadcast(1.0f, x) / Sqrt(distance_squared);
    const V lx = dx * inv_distance;
    const V ly = dy * inv_distance;
    const V lz = dz * inv_distance;
    const V incidence = nx * lx + ny * ly + nz * lz;
    const V off_axis = zero - (Broadcast(c.beam_x[k], x) * lx + Broadcast(c.beam_y[k], x) * ly +
                               Broadcast(c.beam_z[k], x) * lz);
    // Irradiance: beam pattern, inverse square, incidence cosine; none from behind the wall or
    // the LED.
    const V irradiance = Select((incidence > zero) & (off_axis > zero),
                                intensity * Pow(off_axis, c.beam_power, c.beam_exponent) *
                                    incidence * (inv_distance * inv_distance),
                                zero);
    diffuse = diffuse + irradiance;
    if (shiny) {
      const V hx = lx + to_camera_x;
      const V hy = ly + to_camera_y;
      const V hz = lz + to_camera_z;
      const V n_dot_h = (nx * hx + ny * hy + nz * hz) / Sqrt(hx * hx + hy * hy + hz * hz);
      specular =
          specular + Select(n_dot_h > cutoff,
                            irradiance * Pow(n_dot_h, c.specular_power, c.specular_exponent), zero);
    }
  }
  return albedo * Broadcast(static_cast<float>(1.0 / M_PI), x) * diffuse +
         specularity * Broadcast(c.specular_normalisation, x) * specular;
}

}  // namespace

void ShadingBatch::Resize(int size) {
  size_ = size;
  const std::size_t padded = static_cast<std::size_t>((size + kLanes - 1) / kLanes) * kLanes;
  for (auto* v : {&x_, &y_, &z_, &nx_, &ny_, &nz_, &albedo_, &specularity_}) v->resize(padded);
  // Padding lanes shade a harmless point a metre ahead; their results are dropped.
  constexpr float kAhead[3] = {0.0f, 0.0f, 1.0f};
  constexpr float kFacing[3] = {0.0f, 0.0f, -1.0f};
  for (std::size_t i = size; i < padded; ++i) Set(static_cast<int>(i), kAhead, kFacing, 0, 0);
}

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
    led_x_.push_back(static_cast<float>(led.position_cam.x()));
    led_y_.push_back(static_cast<float>(led.position_cam.y()));
    led_z_.push_back(static_cast<float>(led.position_cam.z()));
    beam_x_.push_back(static_cast<float>(led.direction_cam.x()));
    beam_y_.push_back(static_cast<float>(led.direction_cam.y()));
    beam_z_.push_back(static_cast<float>(led.direction_cam.z()));
  }
  // Energy-conserving Blinn-Phong normalisation (m + 8) / (8 pi).
  specular_normalisation_ = (options.specular_exponent + 8.0) / (8.0 * M_PI);
  specular_cutoff_ =
      options.specular_exponent > 0 ? std::exp(std::log(1e-6) / options.specular_exponent) : 0.0;
  beam_power_ = WholePower(options.beam_exponent);
  specular_power_ = WholePower(options.specular_exponent);
  // PIPESCOPE_LIGHTING_SCALAR forces the scalar path, so tests can check both paths agree.
  use_simd_ = std::getenv("PIPESCOPE_LIGHTING_SCALAR") == nullptr;
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

void Lighting::Shade(const ShadingBatch& batch, float* radiance) const {
  const ShadeConstants c{static_cast<int>(leds_.size()),
                         led_x_.data(),
                         led_y_.data(),
                         led_z_.data(),
                         beam_x_.data(),
                         beam_y_.data(),
                         beam_z_.data(),
                         static_cast<float>(options_.intensity),
                         beam_power_,
                         static_cast<float>(options_.beam_exponent),
                         specular_power_,
                         static_cast<float>(options_.specular_exponent),
                         static_cast<float>(specular_cutoff_),
                         static_cast<float>(specular_normalisation_)};
  const int size = batch.size();
  int i = 0;
#ifdef PIPESCOPE_LIGHTING_SSE2
  if (use_simd_) {
    // The batch is padded to whole registers; the padding's results are dropped.
    for (; i < size; i += ShadingBatch::kLanes) {
      const auto load = [i](const std::vector<float>& v) { return F4{_mm_loadu_ps(&v[i])}; };
      const F4 specularity = load(batch.specularity_);
      const bool shiny = _mm_movemask_ps(_mm_cmpgt_ps(specularity.v, _mm_setzero_ps())) != 0;
      const F4 result =
          ShadeLanes(c, load(batch.x_), load(batch.y_), load(batch.z_), load(batch.nx_),
                     load(batch.ny_), load(batch.nz_), load(batch.albedo_), specularity, shiny);
      alignas(16) float lanes[ShadingBatch::kLanes];
      _mm_store_ps(lanes, result.v);
      std::copy(lanes, lanes + std::min(ShadingBatch::kLanes, size - i), radiance + i);
    }
  }
#endif
  for (; i < size; ++i) {
    radiance[i] = ShadeLanes(c, batch.x_[i], batch.y_[i], batch.z_[i], batch.nx_[i], batch.ny_[i],
                             batch.nz_[i], batch.albedo_[i], batch.specularity_[i],
                             batch.specularity_[i] > 0.0f);
  }
}

}  // namespace pipescope
