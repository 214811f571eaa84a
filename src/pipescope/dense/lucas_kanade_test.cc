#include "pipescope/dense/lucas_kanade.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "pipescope/dense/testing.h"

namespace pipescope {
namespace {

TEST(LucasKanade, RecoversSubPixelShifts) {
  int seed = 20;
  for (const cv::Point2d shift : {cv::Point2d(0.23, 0.41), cv::Point2d(3.37, -1.62),
                                  cv::Point2d(-7.81, 4.25), cv::Point2d(-0.5, 0.5)}) {
    for (const cv::Size size : {cv::Size(256, 192), cv::Size(160, 120)}) {
      const RegistrationPair pair = MakeRegistrationPair(size, shift, 0.0, 1.0, ++seed);
      const LucasKanadeResult result = RegisterLucasKanade(pair.reference, pair.next);
      EXPECT_TRUE(result.converged);
      EXPECT_LE(Distance(result.shift, shift), 0.05) << shift << " " << size << result.shift;
      // The residual is the two images' noise (sigma 1 each), slightly smoothed by the
      // interpolation of `next`.
      EXPECT_GT(result.rms_residual, 1.0);
      EXPECT_LT(result.rms_residual, 1.6);
      EXPECT_GT(result.iterations, result.final_level_iterations);
      EXPECT_GT(result.num_pixels, size.area() / 2);
    }
  }
}

TEST(LucasKanade, PyramidReachesLargeShiftsFromZero) {
  const cv::Point2d shift(13.6, -6.3);
  const RegistrationPair pair = MakeRegistrationPair({256, 192}, shift, 0.0, 1.0, 3);
  const LucasKanadeResult result = RegisterLucasKanade(pair.reference, pair.next);
  EXPECT_TRUE(result.converged);
  EXPECT_LE(Distance(result.shift, shift), 0.05) << result.shift;
  // A single level gets there from a nearby initial guess.
  LucasKanadeOptions single;
  single.num_levels = 1;
  const LucasKanadeResult from_guess =
      RegisterLucasKanade(pair.reference, pair.next, single, {14.0, -6.0});
  EXPECT_TRUE(from_guess.converged);
  EXPECT_LE(Distance(from_guess.shift, shift), 0.05) << from_guess.shift;
}

// A shift that settles next to a whole pixel, as the shift across the pipe does (about 0): the
// pixels compared must not change with floor(t), or Gauss-Newton can cycle between the two sets
// on either side of it and never converge (33 of 1460 steel-6in pairs without sheen did).
TEST(LucasKanade, ConvergesNextToAWholePixel) {
  int converged = 0, pairs = 0;
  for (const double y : {1e-5, -1e-5, 3e-5, -3e-5, 1e-4, -1e-4}) {
    for (int seed = 1; seed <= 4; ++seed, ++pairs) {
      const cv::Point2d shift(10.37, y);
      RegistrationPair pair = MakeRegistrationPair({256, 96}, shift, 0.0, 1.0, seed);
      // Edge rows that disagree with the texture (a resampled frame's border): whether the
      // warp's first and last rows are compared changes the minimum noticeably.
      pair.next.row(1).setTo(255.0);
      pair.next.row(pair.next.rows - 2).setTo(0.0);
      const LucasKanadeResult result =
          RegisterLucasKanade(pair.reference, pair.next, {}, {10.0, 0.0});
      converged += result.converged ? 1 : 0;
      EXPECT_LE(Distance(result.shift, shift), 0.05) << y << " seed " << seed;
    }
  }
  EXPECT_EQ(converged, pairs);  // 18 of 24 when the set followed floor(t)
}

TEST(LucasKanade, ConvergesToTightTolerance) {
  const RegistrationPair pair = MakeRegistrationPair({160, 120}, {2.2, 1.1}, 0.0, 0.0, 4);
  LucasKanadeOptions options;
  const LucasKanadeResult result = RegisterLucasKanade(pair.reference, pair.next, options);
  ASSERT_TRUE(result.converged);
  // Restarting from the result moves it by less than the tolerance.
  options.num_levels = 1;
  const LucasKanadeResult again =
      RegisterLucasKanade(pair.reference, pair.next, options, result.shift);
  EXPECT_TRUE(again.converged);
  EXPECT_LE(again.final_level_iterations, 2);
  EXPECT_LT(Distance(again.shift, result.shift), 2e-4);
  // Noise-free: the residual is only the interpolation error.
  EXPECT_LT(result.rms_residual, 0.2);
  EXPECT_LE(Distance(result.shift, {2.2, 1.1}), 0.01);
}

TEST(LucasKanade, BilinearInterpolation) {
  const cv::Point2d shift(-2.71, 3.14);
  const RegistrationPair pair = MakeRegistrationPair({256, 192}, shift, 0.0, 1.0, 5);
  LucasKanadeOptions options;
  options.interpolation = ShiftInterpolation::kBilinear;
  const LucasKanadeResult result = RegisterLucasKanade(pair.reference, pair.next, options);
  EXPECT_TRUE(result.converged);
  EXPECT_LE(Distance(result.shift, shift), 0.05) << result.shift;
}

TEST(LucasKanade, EstimatesGainAndBias) {
  const cv::Point2d shift(4.4, -2.7);
  const RegistrationPair pair =
      MakeRegistrationPair({256, 192}, shift, 0.0, 1.0, 6, /*gain=*/1.3, /*bias=*/-25.0);
  LucasKanadeOptions options;
  options.estimate_gain_bias = true;
  const LucasKanadeResult result = RegisterLucasKanade(pair.reference, pair.next, options);
  EXPECT_TRUE(result.converged);
  EXPECT_LE(Distance(result.shift, shift), 0.05) << result.shift;
  EXPECT_NEAR(result.gain, 1.3, 0.01);
  EXPECT_NEAR(result.bias, -25.0, 1.5);
  EXPECT_LT(result.rms_residual, 1.8);
}

// A pair made by resampling an image, as 000's test pairs would be: cv::warpAffine quantises
// sub-pixel positions to 1/32 px, so the shift is a multiple of 1/32.
TEST(LucasKanade, RecoversShiftOfWarpedImage) {
  cv::Mat texture(192, 256, CV_32F);
  cv::RNG rng(7);
  rng.fill(texture, cv::RNG::UNIFORM, 0.0, 255.0);
  cv::GaussianBlur(texture, texture, cv::Size(), 2.0);
  const cv::Point2d shift(77.0 / 32.0, -41.0 / 32.0);
  // next(x + t) = texture(x): warpAffine's forward map x -> x + t.
  const cv::Matx23d forward(1, 0, shift.x, 0, 1, shift.y);
  cv::Mat next;
  cv::warpAffine(texture, next, forward, texture.size(), cv::INTER_CUBIC, cv::BORDER_REFLECT_101);
  const LucasKanadeResult result = RegisterLucasKanade(texture, next);
  EXPECT_TRUE(result.converged);
  EXPECT_LE(Distance(result.shift, shift), 0.05) << result.shift;
}

TEST(LucasKanade, FlatImageDoesNotConverge) {
  const cv::Mat flat(120, 160, CV_32F, cv::Scalar(50.0));
  const LucasKanadeResult result = RegisterLucasKanade(flat, flat);
  EXPECT_FALSE(result.converged);
  // Texture in one direction only (vertical stripes) leaves ty unobservable.
  cv::Mat stripes(120, 160, CV_32F);
  for (int y = 0; y < stripes.rows; ++y) {
    for (int x = 0; x < stripes.cols; ++x) stripes.at<float>(y, x) = 100.f * std::sin(0.3 * x);
  }
  EXPECT_FALSE(RegisterLucasKanade(stripes, stripes).converged);
}

}  // namespace
}  // namespace pipescope
