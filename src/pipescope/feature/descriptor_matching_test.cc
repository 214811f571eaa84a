#include "pipescope/feature/descriptor_matching.h"

#include <gtest/gtest.h>

#include <numeric>
#include <opencv2/features2d.hpp>
#include <random>

#include "pipescope/feature/key_frame_selection.h"

namespace pipescope {
namespace {

TEST(MatchDescriptors, RecoversAPermutationAndRejectsAmbiguousRows) {
  std::mt19937 random(3);
  std::normal_distribution<float> noise(0.f, 1.f);
  cv::Mat first(200, 128, CV_32F);
  for (int r = 0; r < first.rows; ++r)
    for (int c = 0; c < 128; ++c) first.at<float>(r, c) = 10.f * noise(random);
  std::vector<int> permutation(200);
  std::iota(permutation.begin(), permutation.end(), 0);
  std::shuffle(permutation.begin(), permutation.end(), random);
  cv::Mat second(200, 128, CV_32F);
  for (int r = 0; r < 200; ++r) {
    for (int c = 0; c < 128; ++c)
      second.at<float>(permutation[r], c) = first.at<float>(r, c) + 0.5f * noise(random);
  }
  // Row 0's match gets a near twin in `second` (replacing row 1's match): row 0 is ambiguous
  // and row 1 has no match; the ratio test drops both.
  for (int c = 0; c < 128; ++c) {
    second.at<float>(permutation[1], c) = first.at<float>(0, c) + 0.5f * noise(random);
  }
  const std::vector<IndexMatch> matches = MatchDescriptors(first, second, {});
  int correct = 0;
  for (const IndexMatch& m : matches) {
    EXPECT_GT(m.first, 1);
    if (permutation[m.first] == m.second) ++correct;
  }
  EXPECT_EQ(correct, static_cast<int>(matches.size()));
  EXPECT_GE(correct, 196);
}

TEST(MatchDescriptors, EqualsOpenCvBruteForceRatioAndMutualCheck) {
  // Oracle: cv::BFMatcher's two nearest neighbours each way. `second` holds noisy copies of
  // rows of `first`, from nearly exact to lost in the noise, and copies of a few rows twice (so
  // that rows fail the ratio test and the mutual check for both reasons).
  std::mt19937 random(5);
  std::normal_distribution<float> noise(0.f, 1.f);
  std::uniform_real_distribution<float> spread(0.5f, 12.f);
  std::uniform_int_distribution<int> row(0, 299);
  cv::Mat first(300, 128, CV_32F), second(280, 128, CV_32F);
  cv::randn(first, 0.0, 10.0);
  for (int r = 0; r < second.rows; ++r) {
    const int source = r < 240 ? row(random) : r - 240;
    const float sigma = spread(random);
    for (int k = 0; k < 128; ++k) {
      second.at<float>(r, k) = first.at<float>(source, k) + sigma * noise(random);
    }
  }
  const DescriptorMatchingOptions options;
  cv::BFMatcher matcher(cv::NORM_L2);
  std::vector<std::vector<cv::DMatch>> forward, backward;
  matcher.knnMatch(first, second, forward, 2);
  matcher.knnMatch(second, first, backward, 1);
  std::vector<std::pair<int, int>> expected;
  for (const std::vector<cv::DMatch>& best : forward) {
    if (!(best[0].distance < options.max_ratio * best[1].distance)) continue;
    if (backward[best[0].trainIdx][0].trainIdx != best[0].queryIdx) continue;
    expected.emplace_back(best[0].queryIdx, best[0].trainIdx);
  }
  std::vector<std::pair<int, int>> ours;
  for (const IndexMatch& m : MatchDescriptors(first, second, options)) {
    ours.emplace_back(m.first, m.second);
  }
  ASSERT_GT(expected.size(), 30u);
  ASSERT_LT(expected.size(), 250u);
  EXPECT_EQ(ours, expected);
}

TEST(KeyFrameSelection, EndsOnFewCorrespondencesOrLargeFlow) {
  KeyFrameOptions options;
  EXPECT_NEAR(MedianFlow({{0, 0}, {0, 0}, {0, 0}}, {{3, 4}, {6, 8}, {0, 1}}), 5.0, 1e-9);
  EXPECT_FALSE(EndsKeyFrameSpan(200, 0, 10.0, 1000, options));
  EXPECT_TRUE(EndsKeyFrameSpan(100, 0, 10.0, 1000, options));
  EXPECT_TRUE(EndsKeyFrameSpan(200, 0, 151.0, 1000, options));
  // A span that started rich keeps 000's absolute minimum.
  EXPECT_TRUE(EndsKeyFrameSpan(100, 600, 10.0, 1000, options));
}

// On faint texture a span starts with few correspondences: it ends when half of them are lost,
// not at once for want of 150; the flow limit still holds.
TEST(KeyFrameSelection, APoorSpanEndsOnTheShareLost) {
  KeyFrameOptions options;
  EXPECT_FALSE(EndsKeyFrameSpan(30, 60, 10.0, 1000, options));
  EXPECT_TRUE(EndsKeyFrameSpan(29, 60, 10.0, 1000, options));
  EXPECT_TRUE(EndsKeyFrameSpan(60, 60, 151.0, 1000, options));
  options.min_correspondence_fraction = 0.0;  // 000's rule alone
  EXPECT_TRUE(EndsKeyFrameSpan(59, 60, 10.0, 1000, options));
}

}  // namespace
}  // namespace pipescope
