#include "pipescope/mapping/mosaic_io.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgcodecs.hpp>

#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

TEST(MosaicToGrey8, StretchesPercentilesAndBlanksEmptyCells) {
  cv::Mat mosaic(30, 40, CV_32F, cv::Scalar(NAN));
  // Values 0..999 in the first 25 rows; the rest empty.
  for (int i = 0; i < 1000; ++i) mosaic.at<float>(i / 40, i % 40) = static_cast<float>(i);
  const cv::Mat grey = MosaicToGrey8(mosaic);
  ASSERT_EQ(grey.type(), CV_8U);
  ASSERT_EQ(grey.size(), mosaic.size());
  // Percentiles interpolate the order statistics: 0.005 * 999 and 0.995 * 999.
  const double low = 4.995, high = 994.005;
  for (const int value : {0, 3, 5, 100, 500, 900, 994, 995, 999}) {
    const double expected =
        std::clamp(std::round((value - low) * 255.0 / (high - low)), 0.0, 255.0);
    EXPECT_EQ(grey.at<uchar>(value / 40, value % 40), expected) << value;
  }
  EXPECT_EQ(grey.at<uchar>(0, 0), 0);
  EXPECT_EQ(grey.at<uchar>(24, 39), 255);
  EXPECT_EQ(cv::countNonZero(grey(cv::Rect(0, 25, 40, 5))), 0);
}

TEST(MosaicToGrey8, EmptyAndConstantMosaics) {
  const cv::Mat empty(5, 6, CV_32F, cv::Scalar(NAN));
  EXPECT_EQ(cv::countNonZero(MosaicToGrey8(empty)), 0);
  cv::Mat constant = empty.clone();
  constant.at<float>(2, 3) = 7.0f;
  constant.at<float>(4, 5) = 7.0f;
  const cv::Mat grey = MosaicToGrey8(constant);
  EXPECT_EQ(grey.at<uchar>(2, 3), 128);
  EXPECT_EQ(cv::countNonZero(grey), 2);
}

TEST(WriteMosaicPng, WritesAnEightBitPngAtomically) {
  const auto dir = MakeTestDirectory("mosaic_io");
  cv::Mat mosaic(20, 300, CV_32F, cv::Scalar(NAN));
  cv::randu(mosaic(cv::Rect(10, 5, 200, 10)), 0.0, 1000.0);
  const auto path = dir / "sub" / "mosaic.png";
  WriteMosaicPng(path, mosaic);
  const cv::Mat read = cv::imread(path.string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(read.type(), CV_8U);
  EXPECT_EQ(cv::norm(read, MosaicToGrey8(mosaic), cv::NORM_INF), 0.0);
  // Only the PNG: no temporary left behind.
  int files = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir / "sub")) {
    ++files;
  }
  EXPECT_EQ(files, 1);
  // A folder that cannot be made (its parent is a file) is the user's to fix.
  const std::string message =
      InputErrorMessage([&] { WriteMosaicPng(path / "mosaic.png", mosaic); });
  EXPECT_NE(message.find("mosaic.png"), std::string::npos) << message;
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace pipescope
