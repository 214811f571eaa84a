#include "pipescope/feature/sparse_features.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <opencv2/imgproc.hpp>

namespace pipescope {
namespace {

// A weak, blotchy wall (texture of a few grey levels over tens of pixels) under sensor noise of
// sigma 4: the condition where the sparse front end lost its tracks (docs/conditions.md).
cv::Mat BlotchyWall(int width, int height) {
  cv::Mat texture(height, width, CV_32F);
  cv::RNG rng(7);
  rng.fill(texture, cv::RNG::NORMAL, 0.0, 1.0);
  cv::GaussianBlur(texture, texture, cv::Size(), 6.0);
  cv::normalize(texture, texture, 90.0, 110.0, cv::NORM_MINMAX);
  return texture;
}

cv::Mat Noisy(const cv::Mat& clean, std::uint64_t seed) {
  cv::Mat noise(clean.size(), CV_32F);
  cv::RNG rng(seed);
  rng.fill(noise, cv::RNG::NORMAL, 0.0, 4.0);
  cv::Mat image;
  cv::Mat(clean + noise).convertTo(image, CV_8U);
  return image;
}

int InliersBetweenShiftedViews(double blur_sigma_px) {
  const Camera camera(CameraModelId::kPinholeRadtan, 640, 480,
                      {500, 500, 319.5, 239.5, 0, 0, 0, 0, 0});
  const cv::Mat wall = BlotchyWall(700, 480);
  // The second view is the first moved 12 px along x, with its own noise.
  const cv::Mat first = Noisy(wall(cv::Rect(0, 0, 640, 480)), 1);
  const cv::Mat second = Noisy(wall(cv::Rect(12, 0, 640, 480)), 2);
  SparseFeatureOptions options;
  options.blur_sigma_px = blur_sigma_px;
  const SparseFeatures features(camera, options);
  const FrameFeatures a = features.Extract(first, nullptr);
  const FrameFeatures b = features.Extract(second, nullptr);
  const PairMatches matches = features.Match(a, b, nullptr);
  int correct = 0;
  for (const IndexMatch& match : matches.inliers) {
    const cv::Point2f flow = b.keypoints[match.second].position - a.keypoints[match.first].position;
    correct += std::abs(flow.x + 12.0f) < 1.5f && std::abs(flow.y) < 1.5f;
  }
  std::printf("blur %.1f px: %zu inliers, %d of them within 1.5 px of the true shift\n",
              blur_sigma_px, matches.inliers.size(), correct);
  return correct;
}

TEST(SparseFeatures, BlurBeforeDetectionKeepsTracksOnAWeakNoisyWall) {
  const int plain = InliersBetweenShiftedViews(0.0);
  const int blurred = InliersBetweenShiftedViews(3.0);
  EXPECT_GT(blurred, 2 * plain);
  EXPECT_GT(blurred, 50);
}

}  // namespace
}  // namespace pipescope
