#include "pipescope/synthetic/sensor.h"

#include <gtest/gtest.h>

#include <cmath>

namespace pipescope {
namespace {

TEST(Sensor, VignettingIsOneAtCentreAndFallsToTheCorner) {
  const Camera camera(CameraModelId::kPinholeRadtan, 101, 81, {100, 100, 50, 40, 0, 0, 0, 0, 0});
  const cv::Mat map = VignettingMap(camera, 0.3);
  EXPECT_FLOAT_EQ(map.at<float>(40, 50), 1.0f);
  EXPECT_NEAR(map.at<float>(0, 0), 0.7f, 1e-6);
  EXPECT_NEAR(map.at<float>(80, 100), 0.7f, 1e-6);
  EXPECT_NEAR(map.at<float>(40, 100), 1.0f - 0.3f * 2500.0f / 4100.0f, 1e-6);
}

TEST(Sensor, ExposureClippingAndQuantisationWithoutNoise) {
  cv::Mat radiance(2, 3, CV_32F);
  radiance.at<float>(0, 0) = 0.0f;
  radiance.at<float>(0, 1) = 1.0f;
  radiance.at<float>(0, 2) = 2.26f;
  radiance.at<float>(1, 0) = 100.0f;
  radiance.at<float>(1, 1) = -1.0f;
  radiance.at<float>(1, 2) = 2.0f;
  cv::Mat vignetting(2, 3, CV_32F, cv::Scalar(1.0f));
  vignetting.at<float>(1, 2) = 0.5f;
  SensorOptions options;
  options.exposure = 50.0;
  options.noise_sigma = 0.0;
  options.electrons_per_grey_level = 0.0;
  const cv::Mat image = ApplySensor(radiance, vignetting, options, 1);
  EXPECT_EQ(image.at<std::uint8_t>(0, 0), 0);
  EXPECT_EQ(image.at<std::uint8_t>(0, 1), 50);
  EXPECT_EQ(image.at<std::uint8_t>(0, 2), 113);  // 113.0 rounds to 113
  EXPECT_EQ(image.at<std::uint8_t>(1, 0), 255);  // saturates
  EXPECT_EQ(image.at<std::uint8_t>(1, 1), 0);
  EXPECT_EQ(image.at<std::uint8_t>(1, 2), 50);  // vignetting halves it
}

TEST(Sensor, ReadAndShotNoiseHaveTheModelledSpread) {
  const cv::Mat radiance(200, 200, CV_32F, cv::Scalar(1.0f));
  const cv::Mat vignetting(200, 200, CV_32F, cv::Scalar(1.0f));
  SensorOptions options;
  options.exposure = 100.0;
  options.noise_sigma = 2.0;
  options.electrons_per_grey_level = 25.0;
  const cv::Mat image = ApplySensor(radiance, vignetting, options, 7);
  cv::Scalar mean, stddev;
  cv::meanStdDev(image, mean, stddev);
  // variance = read^2 + signal / e, plus 1/12 from rounding.
  const double expected = std::sqrt(4.0 + 100.0 / 25.0 + 1.0 / 12.0);
  EXPECT_NEAR(mean[0], 100.0, 0.1);
  EXPECT_NEAR(stddev[0], expected, 0.05 * expected);
  // Same seed, same bytes; another seed, other bytes.
  EXPECT_EQ(cv::norm(image, ApplySensor(radiance, vignetting, options, 7), cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(image, ApplySensor(radiance, vignetting, options, 8), cv::NORM_INF), 0.0);
}

}  // namespace
}  // namespace pipescope
