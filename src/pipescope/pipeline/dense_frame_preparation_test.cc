#include "pipescope/pipeline/dense_frame_preparation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "pipescope/image/gain_mask.h"

namespace pipescope {
namespace {

// A smooth random texture in 8-bit grey levels and a vignetting-like gain mask.
cv::Mat Texture(cv::Size size) {
  cv::Mat noise(size, CV_32F);
  cv::randu(noise, 0.0, 255.0);
  cv::GaussianBlur(noise, noise, cv::Size(), 2.0);
  cv::Mat texture;
  cv::normalize(noise, texture, 20.0, 230.0, cv::NORM_MINMAX);
  return texture;
}

cv::Mat Vignetting(cv::Size size) {
  cv::Mat mask(size, CV_32F);
  for (int y = 0; y < size.height; ++y) {
    for (int x = 0; x < size.width; ++x) {
      const double r2 = (std::pow(x - 0.45 * size.width, 2) + std::pow(y - 0.55 * size.height, 2)) /
                        (size.width * size.width);
      mask.at<float>(y, x) = static_cast<float>(std::exp(-2.0 * r2));
    }
  }
  return mask;
}

TEST(WeightedBlockMean, EqualsMultiplyThenAreaResize) {
  const cv::Mat image = Texture({203, 151});  // not whole blocks: the last ones are dropped
  const cv::Mat weight = Vignetting(image.size());
  for (const int factor : {1, 2, 4, 5}) {
    const cv::Size size(image.cols / factor, image.rows / factor);
    const cv::Rect whole(0, 0, size.width * factor, size.height * factor);
    cv::Mat product, expected;
    cv::multiply(image, weight, product);
    cv::resize(product(whole), expected, size, 0, 0, cv::INTER_AREA);
    const cv::Mat result = WeightedBlockMean(image, weight, factor, 0.5f);
    EXPECT_LE(cv::norm(result, 0.5 * expected, cv::NORM_INF), 1e-3) << "factor " << factor;
    cv::Mat plain;
    cv::resize(image(whole), plain, size, 0, 0, cv::INTER_AREA);
    EXPECT_LE(cv::norm(DownsampleByBlockMean(image, factor), plain, cv::NORM_INF), 1e-3);
  }
  // 8- and 16-bit input, scaled to grey levels, give the float input's result.
  cv::Mat image8, image16;
  image.convertTo(image8, CV_8U);
  image8.convertTo(image16, CV_16U, 257.0);
  cv::Mat image8_float;
  image8.convertTo(image8_float, CV_32F);
  const cv::Mat expected = WeightedBlockMean(image8_float, weight, 4);
  EXPECT_LE(cv::norm(WeightedBlockMean(image8, weight, 4), expected, cv::NORM_INF), 1e-3);
  EXPECT_LE(
      cv::norm(WeightedBlockMean(image16, weight, 4, 255.0f / 65535.0f), expected, cv::NORM_INF),
      1e-3);
}

// Prepare() undistorts before it corrects the gain; the order of 000 §4.2 corrects first. The
// two agree because the mask is smooth.
TEST(DenseFramePreparation, MatchesGainCorrectionThenUndistortionThenBlockMean) {
  const Camera camera(CameraModelId::kPinholeRadtan, 320, 240,
                      {260.0, 261.0, 158.0, 121.0, -0.2, 0.05, 0.001, -0.001, 0.0});
  const cv::Mat texture = Texture({camera.Width(), camera.Height()});
  const cv::Mat mask = Vignetting({camera.Width(), camera.Height()});
  cv::Mat frame;  // what the camera records: the texture darkened by the mask
  cv::multiply(texture, mask, frame);
  const DenseFramePreparation preparation(camera, mask, {.downsample = 4});

  const Undistorter undistorter(camera);
  const cv::Mat expected = DownsampleByBlockMean(undistorter.Apply(ApplyGainMask(frame, mask)), 4);
  // Away from the border, where the rectified image runs off the recorded one.
  const cv::Rect inner(4, 4, expected.cols - 8, expected.rows - 8);

  const cv::Mat from_float = preparation.Prepare(frame);
  ASSERT_EQ(from_float.size(), preparation.PreparedSize());
  EXPECT_LE(cv::norm(from_float(inner), expected(inner), cv::NORM_INF), 0.05);

  // An 8-bit frame is rectified in 8 bits: rounding to whole grey levels before the correction
  // adds at most half a level times the correction factor to a pixel, and averages out over the
  // block.
  cv::Mat frame8;
  frame.convertTo(frame8, CV_8U);
  cv::Mat frame8_float;
  frame8.convertTo(frame8_float, CV_32F);
  const cv::Mat expected8 =
      DownsampleByBlockMean(undistorter.Apply(ApplyGainMask(frame8_float, mask)), 4);
  const cv::Mat difference = preparation.Prepare(frame8)(inner) - expected8(inner);
  EXPECT_LE(cv::norm(difference, cv::NORM_L2) / std::sqrt(inner.area()), 0.25);
  EXPECT_LE(cv::norm(difference, cv::NORM_INF), 1.0);
}

}  // namespace
}  // namespace pipescope
