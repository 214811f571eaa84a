#include "pipescope/synthetic/sensor.h"

#include <algorithm>
#include <cmath>

#include "pipescope/image/undistortion.h"

namespace pipescope {

cv::Mat VignettingMap(const Camera& camera, double vignetting) {
  // The optical centre of every model is its principal point; the corner farthest from it is
  // where the fall-off reaches its full value.
  const cv::Point2d principal_point = PrincipalPoint(camera);
  const Eigen::Vector2d centre(principal_point.x, principal_point.y);
  const double w = camera.Width() - 1.0;
  const double h = camera.Height() - 1.0;
  const double max_radius_squared =
      std::max({centre.squaredNorm(), (centre - Eigen::Vector2d(w, 0)).squaredNorm(),
                (centre - Eigen::Vector2d(0, h)).squaredNorm(),
                (centre - Eigen::Vector2d(w, h)).squaredNorm()});
  cv::Mat map(camera.Height(), camera.Width(), CV_32F);
  for (int y = 0; y < map.rows; ++y) {
    float* row = map.ptr<float>(y);
    for (int x = 0; x < map.cols; ++x) {
      const double r2 = (Eigen::Vector2d(x, y) - centre).squaredNorm() / max_radius_squared;
      row[x] = static_cast<float>(std::max(0.0, 1.0 - vignetting * r2));
    }
  }
  return map;
}

cv::Mat ApplySensor(const cv::Mat& radiance, const cv::Mat& vignetting,
                    const SensorOptions& options, std::uint64_t seed) {
  CV_Assert(radiance.type() == CV_32F && vignetting.type() == CV_32F &&
            radiance.size() == vignetting.size());
  cv::RNG rng(seed);
  cv::Mat image(radiance.size(), CV_8U);
  for (int y = 0; y < radiance.rows; ++y) {
    const float* in = radiance.ptr<float>(y);
    const float* v = vignetting.ptr<float>(y);
    std::uint8_t* out = image.ptr<std::uint8_t>(y);
    for (int x = 0; x < radiance.cols; ++x) {
      const double signal = options.exposure * in[x] * v[x];
      double variance = options.noise_sigma * options.noise_sigma;
      if (options.electrons_per_grey_level > 0) {
        variance += std::max(0.0, signal) / options.electrons_per_grey_level;
      }
      const double value =
          std::clamp(signal + (variance > 0 ? rng.gaussian(std::sqrt(variance)) : 0.0), 0.0, 255.0);
      // std::lround (half away from zero) on [0, 255] without its library call.
      const auto whole = static_cast<int>(value);
      out[x] = static_cast<std::uint8_t>(whole + (value - whole >= 0.5 ? 1 : 0));
    }
  }
  return image;
}

}  // namespace pipescope
