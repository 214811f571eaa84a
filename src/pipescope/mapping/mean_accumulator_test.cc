#include "pipescope/mapping/mean_accumulator.h"

#include <gtest/gtest.h>

#include <cmath>

namespace pipescope {
namespace {

TEST(MeanAccumulator, MeansAcrossTilesAndNegativeCoordinates) {
  MeanAccumulator accumulator(8);
  EXPECT_TRUE(accumulator.Bounds().empty());
  cv::Mat ones(10, 20, CV_32F, cv::Scalar(1.0f));
  cv::Mat threes(10, 20, CV_32F, cv::Scalar(3.0f));
  accumulator.Add(ones, cv::Point(-13, -5));
  accumulator.Add(threes, cv::Point(-3, 0));
  EXPECT_EQ(accumulator.Bounds(), cv::Rect(-13, -5, 30, 15));
  const cv::Mat mean = accumulator.Render(cv::Rect(-20, -10, 40, 30));
  for (int y = -10; y < 20; ++y) {
    for (int x = -20; x < 20; ++x) {
      const bool in_a = x >= -13 && x < 7 && y >= -5 && y < 5;
      const bool in_b = x >= -3 && x < 17 && y >= 0 && y < 10;
      const float value = mean.at<float>(y + 10, x + 20);
      if (in_a && in_b) {
        EXPECT_EQ(value, 2.0f);
      } else if (in_a) {
        EXPECT_EQ(value, 1.0f);
      } else if (in_b) {
        EXPECT_EQ(value, 3.0f);
      } else {
        EXPECT_TRUE(std::isnan(value)) << x << " " << y;
      }
    }
  }
}

TEST(MeanAccumulator, SkipsMaskedAndNonFiniteValues) {
  MeanAccumulator accumulator(4);
  cv::Mat values(3, 3, CV_32F, cv::Scalar(5.0f));
  values.at<float>(0, 0) = NAN;
  values.at<float>(1, 1) = INFINITY;
  cv::Mat mask(3, 3, CV_8U, cv::Scalar(255));
  mask.at<uchar>(2, 2) = 0;
  accumulator.Add(values, cv::Point(10, 10), mask);
  EXPECT_EQ(accumulator.Bounds(), cv::Rect(10, 10, 3, 3));
  const cv::Mat mean = accumulator.Render(cv::Rect(10, 10, 3, 3));
  EXPECT_TRUE(std::isnan(mean.at<float>(0, 0)));
  EXPECT_TRUE(std::isnan(mean.at<float>(1, 1)));
  EXPECT_TRUE(std::isnan(mean.at<float>(2, 2)));
  EXPECT_EQ(mean.at<float>(0, 1), 5.0f);
  EXPECT_EQ(cv::countNonZero(mean == 5.0f), 6);
  // Nothing valid adds nothing, not even to the bounds.
  accumulator.Add(values, cv::Point(100, 100), cv::Mat::zeros(3, 3, CV_8U));
  EXPECT_EQ(accumulator.Bounds(), cv::Rect(10, 10, 3, 3));
}

}  // namespace
}  // namespace pipescope
