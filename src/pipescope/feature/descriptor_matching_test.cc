#include "pipescope/feature/descriptor_matching.h"

#include <gtest/gtest.h>

#include <numeric>
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

TEST(KeyFrameSelection, EndsOnFewCorrespondencesOrLargeFlow) {
  KeyFrameOptions options;
  EXPECT_NEAR(MedianFlow({{0, 0}, {0, 0}, {0, 0}}, {{3, 4}, {6, 8}, {0, 1}}), 5.0, 1e-9);
  EXPECT_FALSE(EndsKeyFrameSpan(200, 10.0, 1000, options));
  EXPECT_TRUE(EndsKeyFrameSpan(100, 10.0, 1000, options));
  EXPECT_TRUE(EndsKeyFrameSpan(200, 151.0, 1000, options));
}

}  // namespace
}  // namespace pipescope
