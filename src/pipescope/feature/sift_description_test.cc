#include "pipescope/feature/sift_description.h"

#include <gtest/gtest.h>

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

namespace pipescope {
namespace {

cv::Mat NoiseTexture(cv::Size size) {
  cv::Mat noise(size, CV_32F);
  cv::randu(noise, 0.f, 255.f);
  cv::Mat texture;
  cv::GaussianBlur(noise, texture, cv::Size(0, 0), 2.0);
  return texture;
}

TEST(DescribeWithSift, EqualsOpenCvSiftAtTheSameKeypointsForAnyLayerCount) {
  // The descriptors of octave-0 keypoints come from the octave's base image, so OpenCV's SIFT
  // with 1, 2 or 3 layers per octave (more or fewer, larger or smaller pyramid blurs) must give
  // exactly ours.
  const cv::Mat image = NoiseTexture({200, 150});
  std::mt19937 random(3);
  std::uniform_real_distribution<float> x(30.f, 170.f), y(30.f, 120.f);
  std::vector<Keypoint> keypoints;
  for (int i = 0; i < 60; ++i) keypoints.push_back({cv::Point2f(x(random), y(random)), 1.f});
  const SiftDescriptionOptions options;
  const cv::Mat ours = DescribeWithSift(image, keypoints, options);
  ASSERT_EQ(ours.rows, 60);
  ASSERT_EQ(ours.cols, 128);
  cv::Mat grey8;
  cv::normalize(image, grey8, 0, 255, cv::NORM_MINMAX, CV_8U);
  for (int layers : {1, 2, 3}) {
    std::vector<cv::KeyPoint> opencv_keypoints;
    for (const Keypoint& k : keypoints) {
      opencv_keypoints.emplace_back(k.position, options.keypoint_size_px, 0.f, k.response, 0);
    }
    cv::Mat opencv;
    cv::SIFT::create(0, layers)->compute(grey8, opencv_keypoints, opencv);
    ASSERT_EQ(opencv.rows, ours.rows) << layers;
    EXPECT_EQ(cv::norm(ours, opencv, cv::NORM_INF), 0.0) << layers << " layers";
  }
}

// The sparse pipeline keeps old key frames' descriptors as bytes for revisits; that is lossless
// only because OpenCV's SIFT values are whole numbers in 0-255.
TEST(DescribeWithSift, DescriptorsSurviveARoundTripThroughBytes) {
  const cv::Mat image = NoiseTexture({200, 150});
  std::vector<Keypoint> keypoints;
  for (int i = 0; i < 40; ++i) {
    keypoints.push_back({cv::Point2f(30.f + 3.3f * i, 40.f + 1.7f * i), 1.f});
  }
  const cv::Mat descriptors = DescribeWithSift(image, keypoints, SiftDescriptionOptions());
  ASSERT_EQ(descriptors.type(), CV_32F);
  cv::Mat bytes, back;
  descriptors.convertTo(bytes, CV_8U);
  bytes.convertTo(back, CV_32F);
  EXPECT_EQ(cv::norm(descriptors, back, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(descriptors, cv::NORM_INF), 100.0);  // not all small
}

}  // namespace
}  // namespace pipescope
