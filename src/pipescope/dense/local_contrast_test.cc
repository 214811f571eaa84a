#include "pipescope/dense/local_contrast.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "pipescope/dense/lucas_kanade.h"
#include "pipescope/dense/testing.h"
#include "pipescope/util/error.h"

namespace pipescope {
namespace {

// RMS of a - b.
double RmsDifference(const cv::Mat& a, const cv::Mat& b) {
  const double norm = cv::norm(a, b, cv::NORM_L2);
  return norm / std::sqrt(static_cast<double>(a.total()));
}

TEST(LocalContrast, IgnoresGainAndOffsetExactly) {
  const RegistrationPair pair = MakeRegistrationPair({160, 120}, {0.0, 0.0}, 0.0, 1.0, 5);
  const cv::Mat normalised = NormaliseLocalContrast(pair.reference, 4.0);
  const cv::Mat scaled = NormaliseLocalContrast(3.5 * pair.reference + 40.0, 4.0);
  EXPECT_LT(RmsDifference(normalised, scaled), 1e-4);
  // Unit local contrast: the RMS over the image is close to 1 (below: the variance floor).
  const double rms = cv::norm(normalised, cv::NORM_L2) / std::sqrt(normalised.total());
  EXPECT_GT(rms, 0.9);
  EXPECT_LT(rms, 1.01);
}

// The formula with OpenCV's own Gaussian blur, zeros outside and every weight blurred in 2D.
TEST(LocalContrast, MatchesTheFormulaByGaussianBlur) {
  const RegistrationPair pair = MakeRegistrationPair({160, 72}, {0.0, 0.0}, 0.0, 1.0, 7);
  const double sigma = 8.0;
  const auto local_mean = [&](const cv::Mat& field) {
    cv::Mat blurred, coverage;
    cv::GaussianBlur(field, blurred, cv::Size(), sigma, 0.0, cv::BORDER_CONSTANT);
    cv::GaussianBlur(cv::Mat::ones(field.size(), CV_32F), coverage, cv::Size(), sigma, 0.0,
                     cv::BORDER_CONSTANT);
    return cv::Mat(blurred / coverage);
  };
  const cv::Mat detail = pair.reference - local_mean(pair.reference);
  const cv::Mat variance = local_mean(detail.mul(detail));
  cv::Mat contrast;
  cv::sqrt(variance + 0.01 * cv::mean(variance)[0], contrast);
  EXPECT_LT(RmsDifference(NormaliseLocalContrast(pair.reference, sigma), detail / contrast), 1e-4);
}

// The wall's texture times a contrast envelope fixed in the frame: a stripe across the motion,
// as the LEDs' sheen leaves after gain correction (docs/dense_vo.md).
cv::Mat WithStripe(const cv::Mat& image, double strength) {
  cv::Mat out = image.clone();
  const double centre = 0.5 * (image.cols - 1), width = 20.0;
  for (int y = 0; y < image.rows; ++y) {
    float* row = out.ptr<float>(y);
    for (int x = 0; x < image.cols; ++x) {
      const double envelope = 1.0 + strength * std::exp(-0.5 * std::pow((x - centre) / width, 2.0));
      row[x] = static_cast<float>(128.0 + envelope * (row[x] - 128.0));
    }
  }
  return out;
}

TEST(LocalContrast, RemovesAnEnvelopeSlowerThanItsScale) {
  const RegistrationPair pair = MakeRegistrationPair({256, 96}, {0.0, 0.0}, 0.0, 0.0, 6);
  const cv::Mat plain = NormaliseLocalContrast(pair.reference, 4.0);
  const cv::Mat striped = NormaliseLocalContrast(WithStripe(pair.reference, 0.6), 4.0);
  // Before normalisation the stripe changes the image by about a third of its contrast.
  const cv::Mat raw_plain = pair.reference - cv::mean(pair.reference)[0];
  const double contrast = cv::norm(raw_plain, cv::NORM_L2) / std::sqrt(raw_plain.total());
  const double raw_change = RmsDifference(pair.reference, WithStripe(pair.reference, 0.6));
  EXPECT_GT(raw_change / contrast, 0.2);
  EXPECT_LT(RmsDifference(plain, striped), 0.25 * raw_change / contrast);
}

// A fixed envelope pulls Gauss-Newton towards zero motion; normalised frames do not, once the
// pixels near the frame's ends along the motion, where the filter is one-sided, are left out.
TEST(LocalContrast, TakesTheFixedEnvelopesPullOffGaussNewton) {
  const cv::Point2d shift(10.3, 0.4);
  constexpr double kSigma = 8.0;
  LucasKanadeOptions without_ends;
  without_ends.border_px = cv::Point2d(2.0 * kSigma, 2.0 * kSigma);
  double raw_error = 0.0, normalised_error = 0.0, with_ends_error = 0.0;
  const int pairs = 6;
  for (int seed = 1; seed <= pairs; ++seed) {
    const RegistrationPair pair = MakeRegistrationPair({256, 96}, shift, 0.0, 1.0, 40 + seed);
    const cv::Mat reference = WithStripe(pair.reference, 0.6);
    const cv::Mat next = WithStripe(pair.next, 0.6);
    const cv::Mat reference_normalised = NormaliseLocalContrast(reference, kSigma);
    const cv::Mat next_normalised = NormaliseLocalContrast(next, kSigma);
    const LucasKanadeResult raw = RegisterLucasKanade(reference, next, {}, {10.0, 0.0});
    const LucasKanadeResult normalised =
        RegisterLucasKanade(reference_normalised, next_normalised, without_ends, {10.0, 0.0});
    const LucasKanadeResult with_ends =
        RegisterLucasKanade(reference_normalised, next_normalised, {}, {10.0, 0.0});
    ASSERT_TRUE(raw.converged);
    ASSERT_TRUE(normalised.converged);
    raw_error += (raw.shift.x - shift.x) / pairs;
    normalised_error += (normalised.shift.x - shift.x) / pairs;
    with_ends_error += (with_ends.shift.x - shift.x) / pairs;
  }
  std::printf(
      "mean error along the motion: raw %+.4f px, normalised %+.4f px (%+.4f px with the "
      "ends)\n",
      raw_error, normalised_error, with_ends_error);
  EXPECT_LT(raw_error, -0.01);  // towards zero motion (measured -0.018 px)
  EXPECT_LT(std::abs(normalised_error), 0.25 * std::abs(raw_error));  // measured +0.003 px
  EXPECT_LT(with_ends_error, -0.01);                                  // measured -0.016 px
}

TEST(LocalContrast, RejectsBadInput) {
  EXPECT_THROW(NormaliseLocalContrast(cv::Mat(), 4.0), InputError);
  EXPECT_THROW(NormaliseLocalContrast(cv::Mat(8, 8, CV_8UC3), 4.0), InputError);
  EXPECT_THROW(NormaliseLocalContrast(cv::Mat(8, 8, CV_8U), 0.0), InputError);
}

}  // namespace
}  // namespace pipescope
