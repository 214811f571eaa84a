#include "pipescope/image/dense_frame_preparation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "pipescope/image/gain_mask.h"

namespace pipescope {
namespace {

// A smooth random texture in 8-bit grey levels and a vignetting-like gain mask.
cv::Mat Texture(cv::Size size, double blur_sigma_px = 2.0) {
  cv::Mat noise(size, CV_32F);
  cv::randu(noise, 0.0, 255.0);
  cv::GaussianBlur(noise, noise, cv::Size(), blur_sigma_px);
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

// Prepare() is 000 §4.2's gain correction and undistortion followed by the block mean, with the
// last two swapped: the oracle is OpenCV's INTER_AREA resize of the corrected frame, remapped
// with OpenCV's own rectification tables of the camera scaled to the block grid.
TEST(DenseFramePreparation, MatchesOpenCvCorrectionAreaResizeAndRectification) {
  const Camera camera(CameraModelId::kPinholeRadtan, 320, 240,
                      {260.0, 261.0, 158.0, 121.0, -0.2, 0.05, 0.001, -0.001, 0.0});
  const cv::Mat texture = Texture({camera.Width(), camera.Height()});
  const cv::Mat mask = Vignetting({camera.Width(), camera.Height()});
  cv::Mat frame;  // what the camera records: the texture darkened by the mask
  cv::multiply(texture, mask, frame);
  constexpr int kFactor = 4;
  const DenseFramePreparation preparation(camera, mask, {.downsample = kFactor});

  const cv::Size size(camera.Width() / kFactor, camera.Height() / kFactor);
  auto block = [](double full) { return (full + 0.5) / kFactor - 0.5; };
  const cv::Matx33d k(260.0 / kFactor, 0, block(158.0), 0, 261.0 / kFactor, block(121.0), 0, 0, 1);
  const cv::Matx33d new_k(260.0 / kFactor, 0, block(158.0), 0, 260.0 / kFactor, block(121.0), 0, 0,
                          1);
  cv::Mat map_x, map_y;
  cv::initUndistortRectifyMap(k, std::vector<double>{-0.2, 0.05, 0.001, -0.001, 0.0},
                              cv::Matx33d::eye(), new_k, size, CV_32FC1, map_x, map_y);
  auto oracle = [&](const cv::Mat& recorded) {
    cv::Mat recorded_float, corrected, blocks, expected;
    recorded.convertTo(recorded_float, CV_32F);
    cv::multiply(recorded_float, GainCorrectionFactors(mask), corrected);
    cv::resize(corrected, blocks, size, 0, 0, cv::INTER_AREA);
    cv::remap(blocks, expected, map_x, map_y, cv::INTER_CUBIC, cv::BORDER_CONSTANT, 0);
    return expected;
  };
  // Away from the border, where the rectified image runs off the recorded one.
  const cv::Rect inner(2, 2, size.width - 4, size.height - 4);
  const cv::Mat prepared = preparation.Prepare(frame);
  ASSERT_EQ(prepared.size(), preparation.PreparedSize());
  // cv::remap's fixed-point tables quantise the weights to 1/32 px.
  EXPECT_LE(cv::norm(prepared(inner), oracle(frame)(inner), cv::NORM_INF), 0.5);

  // 8-bit frames give the same result as their float copies.
  cv::Mat frame8;
  frame.convertTo(frame8, CV_8U);
  EXPECT_LE(cv::norm(preparation.Prepare(frame8)(inner), oracle(frame8)(inner), cv::NORM_INF), 0.5);

  // The order of 000 §4.2 (undistort at full resolution, then average) differs only by the
  // low-resolution resampling: a few per cent of the contrast of a texture whose detail spans a
  // block (the one above, blurred by 2 px, aliases in 4 px blocks and differs by 18 %).
  cv::Mat smooth_frame;
  cv::multiply(Texture({camera.Width(), camera.Height()}, kFactor), mask, smooth_frame);
  const Undistorter full_resolution(camera);
  const cv::Mat paper_order =
      DownsampleByBlockMean(full_resolution.Apply(ApplyGainMask(smooth_frame, mask)), kFactor);
  cv::Scalar mean, contrast;
  cv::meanStdDev(paper_order(inner), mean, contrast);
  const cv::Mat difference = preparation.Prepare(smooth_frame)(inner) - paper_order(inner);
  EXPECT_LE(cv::norm(difference, cv::NORM_L2) / std::sqrt(inner.area()), 0.05 * contrast[0]);
}

}  // namespace
}  // namespace pipescope
