#pragma once

#include <cstdint>
#include <opencv2/core.hpp>

#include "pipescope/camera/camera.h"

namespace pipescope {

// What the camera does to the light that reaches it: lens vignetting, exposure and gain, shot
// and read noise, 8-bit quantisation with saturation.
struct SensorOptions {
  double exposure = 1.0;                   // grey levels per unit radiance (exposure time x gain)
  double noise_sigma = 1.0;                // read noise, grey levels
  double electrons_per_grey_level = 20.0;  // shot noise: variance = signal / this; 0 = none
};

// Relative illumination of the lens, 1 - vignetting r^2 with r = 1 at the image corner farthest
// from the principal point (CV_32F, camera size).
cv::Mat VignettingMap(const Camera& camera, double vignetting);

// Scales linear radiance (CV_32F) to grey levels, adds noise from a generator seeded with
// `seed`, quantises to 8 bits. Deterministic for a seed.
cv::Mat ApplySensor(const cv::Mat& radiance, const cv::Mat& vignetting,
                    const SensorOptions& options, std::uint64_t seed);

}  // namespace pipescope
