#include "pipescope/image/flat_field.h"

#include <gtest/gtest.h>

#include <cmath>

namespace pipescope {
namespace {

// A fine texture under a smooth light falling off fivefold across the frame comes back as the
// texture alone, at mid-grey: light times albedo divided by the light.
TEST(FlatField, DividesTheShadingOut) {
  const int width = 320, height = 240;
  cv::Mat lit(height, width, CV_8U), albedo(height, width, CV_32F);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const double texture = 1.0 + 0.3 * std::sin(x * 1.3) * std::cos(y * 0.9);
      const double light = 200.0 - 160.0 * x / (width - 1.0);
      albedo.at<float>(y, x) = static_cast<float>(texture);
      lit.at<uchar>(y, x) = cv::saturate_cast<uchar>(light * texture);
    }
  }
  const cv::Mat flat = FlatFieldedGrey8(lit, 8.0);
  ASSERT_EQ(flat.type(), CV_8U);
  // Away from the border (the blur's reflection bends the light there), against 128 x albedo.
  const cv::Rect inner(32, 32, width - 64, height - 64);
  cv::Mat expected, flat32;
  albedo.convertTo(expected, CV_32F, 128.0);
  flat.convertTo(flat32, CV_32F);
  const double worst = cv::norm(flat32(inner), expected(inner), cv::NORM_INF);
  EXPECT_LT(worst, 6.0);
  // The lit frame itself is 80 grey levels brighter on the left than on the right; flat, the
  // two halves' means agree.
  const double left = cv::mean(flat(cv::Rect(32, 32, 64, height - 64)))[0];
  const double right = cv::mean(flat(cv::Rect(width - 96, 32, 64, height - 64)))[0];
  EXPECT_NEAR(left, right, 3.0);
  // sigma 0: the frame itself.
  EXPECT_EQ(cv::norm(FlatFieldedGrey8(lit, 0.0), lit, cv::NORM_INF), 0.0);
}

}  // namespace
}  // namespace pipescope
