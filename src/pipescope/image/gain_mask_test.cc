#include "pipescope/image/gain_mask.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "pipescope/util/error.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

// A radial fall-off like an LED pattern, plus per-image noise.
cv::Mat WhiteCard(int seed) {
  cv::Mat image(60, 80, CV_8U);
  cv::RNG rng(seed);
  for (int y = 0; y < image.rows; ++y) {
    for (int x = 0; x < image.cols; ++x) {
      const double r2 = ((x - 40.0) * (x - 40.0) + (y - 30.0) * (y - 30.0)) / 2500.0;
      image.at<std::uint8_t>(y, x) =
          cv::saturate_cast<std::uint8_t>(200.0 * (1.0 - 0.5 * r2) + rng.gaussian(3.0));
    }
  }
  return image;
}

TEST(GainMask, AveragesSmoothsAndNormalises) {
  std::vector<cv::Mat> cards;
  for (int i = 0; i < 8; ++i) cards.push_back(WhiteCard(i));
  const cv::Mat mask = BuildGainMask(cards, 3.0);
  double max_value = 0.0;
  cv::minMaxLoc(mask, nullptr, &max_value);
  EXPECT_NEAR(max_value, 1.0, 1e-6);
  // The fall-off survives: away from the border (where the blur reflects) the mask is
  // 1 - 0.5 r2 of the centre, less the blur's small constant offset on a quadratic.
  const double r2 = (20.0 * 20.0 + 15.0 * 15.0) / 2500.0;
  EXPECT_NEAR(mask.at<float>(15, 20) / mask.at<float>(30, 40), 1.0 - 0.5 * r2, 0.01);
  // Dividing a white card by the mask flattens it: the spread drops from tens of grey levels
  // to the noise.
  cv::Mat flat;
  cv::Mat card;
  cards[0].convertTo(card, CV_32F);
  cv::divide(card, mask, flat);
  cv::Scalar mean, stddev_before, stddev_after;
  cv::meanStdDev(card, mean, stddev_before);
  cv::meanStdDev(flat, mean, stddev_after);
  EXPECT_GT(stddev_before[0], 20.0);
  EXPECT_LT(stddev_after[0], 5.0);
}

TEST(GainMask, WritesSixteenBitAndReadsBack) {
  const auto dir = MakeTestDirectory("gain_mask");
  const cv::Mat mask = BuildGainMask({WhiteCard(1), WhiteCard(2)}, 2.0);
  WriteGainMask(dir / "gain_mask.png", mask);
  const cv::Mat raw = cv::imread((dir / "gain_mask.png").string(), cv::IMREAD_ANYDEPTH);
  ASSERT_EQ(raw.type(), CV_16U);
  double max_value = 0.0;
  cv::minMaxLoc(raw, nullptr, &max_value);
  EXPECT_EQ(max_value, 65535.0);
  const cv::Mat back = ReadGainMask(dir / "gain_mask.png");
  EXPECT_LT(cv::norm(back, mask, cv::NORM_INF), 1.0 / 65535.0 + 1e-6);
}

TEST(GainMask, BadInputNamesTheProblem) {
  EXPECT_NE(InputErrorMessage([] {
              ReadGainMask("/nonexistent/mask.png");
            }).find("/nonexistent/mask.png"),
            std::string::npos);
  EXPECT_NE(InputErrorMessage([] {
              BuildGainMask({cv::Mat(4, 4, CV_8U, cv::Scalar(9)), cv::Mat(5, 4, CV_8U)}, 1.0);
            }).find("differ in size"),
            std::string::npos);
  EXPECT_NE(
      InputErrorMessage([] { BuildGainMask({cv::Mat::zeros(4, 4, CV_8U)}, 1.0); }).find("black"),
      std::string::npos);
}

}  // namespace
}  // namespace pipescope
