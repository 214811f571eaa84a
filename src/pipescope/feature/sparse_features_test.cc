#include "pipescope/feature/sparse_features.h"

#include <gtest/gtest.h>

#include <algorithm>
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

cv::Mat Noisy(const cv::Mat& clean, std::uint64_t seed, double sigma = 4.0) {
  cv::Mat noise(clean.size(), CV_32F);
  cv::RNG rng(seed);
  rng.fill(noise, cv::RNG::NORMAL, 0.0, sigma);
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

// A wall of fine texture and a second view of it stretched by 4 % along x and moved by a
// sub-pixel shift (as a wall's perspective changes between two views): Harris finds a corner of
// the stretched pattern where its response peaks, which is not where the wall point went, and
// the refinement from the first view's patch finds where the patch went.
TEST(SparseFeatures, RefinedMatchesLieWhereTheWarpPutsThem) {
  const Camera camera(CameraModelId::kPinholeRadtan, 640, 480,
                      {500, 500, 319.5, 239.5, 0, 0, 0, 0, 0});
  cv::Mat wall(480, 640, CV_32F);
  cv::RNG rng(11);
  rng.fill(wall, cv::RNG::NORMAL, 0.0, 1.0);
  cv::GaussianBlur(wall, wall, cv::Size(), 1.5);
  cv::normalize(wall, wall, 60.0, 190.0, cv::NORM_MINMAX);
  // Where a pixel of the first view lies in the second.
  const cv::Matx23d warp(1.04, 0.0, -12.37, 0.0, 1.0, 0.41);
  const auto truth_of = [&](const cv::Point2f& p) {
    return cv::Point2f(static_cast<float>(warp(0, 0) * p.x + warp(0, 1) * p.y + warp(0, 2)),
                       static_cast<float>(warp(1, 0) * p.x + warp(1, 1) * p.y + warp(1, 2)));
  };
  cv::Mat moved;
  cv::warpAffine(wall, moved, cv::Mat(warp), wall.size(), cv::INTER_CUBIC, cv::BORDER_REFLECT);
  const cv::Mat first = Noisy(wall, 1, 2.0);
  const cv::Mat second = Noisy(moved, 2, 2.0);

  SparseFeatureOptions refined_options;
  SparseFeatureOptions plain_options;
  plain_options.match_refinement_window_px = 0;
  const SparseFeatures refined(camera, refined_options), plain(camera, plain_options);
  const FrameFeatures a = refined.Extract(first, nullptr);
  FrameFeatures b = refined.Extract(second, nullptr);
  const PairMatches matches = refined.Match(a, b, nullptr);
  const PairMatches plain_matches =
      plain.Match(plain.Extract(first, nullptr), plain.Extract(second, nullptr), nullptr);
  ASSERT_EQ(matches.refined_positions.size(), matches.inliers.size());
  ASSERT_TRUE(plain_matches.refined_positions.empty());
  ASSERT_GT(matches.inliers.size(), 100u);

  auto errors_of = [&](const PairMatches& pairs, const FrameFeatures& from,
                       const FrameFeatures& to) {
    std::vector<double> errors;
    for (const IndexMatch& match : pairs.inliers) {
      const cv::Point2f truth = truth_of(from.keypoints[match.first].position);
      errors.push_back(cv::norm(to.keypoints[match.second].position - truth));
    }
    std::sort(errors.begin(), errors.end());
    return errors[errors.size() / 2];
  };
  const double harris_error = errors_of(matches, a, b);
  SparseFeatures::AdoptRefinedPositions(matches, &b);
  const double refined_error = errors_of(matches, a, b);
  std::printf("median error of %zu matches: at the Harris corners %.3f px, refined %.3f px\n",
              matches.inliers.size(), harris_error, refined_error);
  // Measured: 0.144 and 0.051 px.
  EXPECT_GT(harris_error, 0.1);
  EXPECT_LT(refined_error, 0.08);
  EXPECT_LT(refined_error, harris_error / 2.0);
  // The adopted bearings are the refined positions' own.
  for (std::size_t i = 0; i < matches.inliers.size(); ++i) {
    const int index = matches.inliers[i].second;
    const cv::Point2f& p = b.keypoints[index].position;
    Eigen::Vector3d bearing;
    ASSERT_TRUE(camera.Unproject(Eigen::Vector2d(p.x, p.y), &bearing));
    EXPECT_LT((bearing - b.bearings[index]).norm(), 1e-9);
  }
}

}  // namespace
}  // namespace pipescope
