#include "pipescope/dense/phase_correlation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <opencv2/imgproc.hpp>

#include "pipescope/dense/testing.h"

namespace pipescope {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

TEST(PhaseCorrelation, RecoversSubPixelShifts) {
  int seed = 80;
  for (const cv::Point2d shift : {cv::Point2d(0.23, 0.41), cv::Point2d(3.37, -1.62),
                                  cv::Point2d(-17.81, 6.25), cv::Point2d(-0.5, 0.5)}) {
    for (const cv::Size size : {cv::Size(256, 192), cv::Size(160, 120)}) {
      const RegistrationPair pair = MakeRegistrationPair(size, shift, 0.0, 1.0, ++seed);
      const PhaseCorrelationResult result = RegisterPhaseCorrelation(pair.reference, pair.next);
      EXPECT_LE(Distance(result.shift, shift), 0.05) << shift << " " << size << result.shift;
      EXPECT_EQ(result.rotation_rad, 0.0);
      EXPECT_GT(result.peak, 0.2);
    }
  }
}

TEST(PhaseCorrelation, SimplerPeakMethodsAreCoarser) {
  const cv::Point2d shift(5.3, -2.2);
  const RegistrationPair pair = MakeRegistrationPair({256, 192}, shift, 0.0, 1.0, 7);
  PhaseCorrelationOptions options;
  options.peak_method = PhasePeakMethod::kParabolic;
  EXPECT_LE(Distance(RegisterPhaseCorrelation(pair.reference, pair.next, options).shift, shift),
            0.25);
  options.peak_method = PhasePeakMethod::kCentroid3x3;
  EXPECT_LE(Distance(RegisterPhaseCorrelation(pair.reference, pair.next, options).shift, shift),
            0.4);
}

TEST(PhaseCorrelation, AgreesWithOpenCvPhaseCorrelate) {
  int seed = 90;
  for (const cv::Point2d shift : {cv::Point2d(2.0, -1.0), cv::Point2d(-13.0, 7.0),
                                  cv::Point2d(-9.4, 3.6), cv::Point2d(14.25, 10.5)}) {
    const RegistrationPair pair = MakeRegistrationPair({256, 192}, shift, 0.0, 1.0, ++seed);
    cv::Mat window;
    cv::createHanningWindow(window, pair.reference.size(), CV_32F);
    // Same sign convention: cv::phaseCorrelate(a, b) is the shift of b's content relative to a.
    const cv::Point2d opencv = cv::phaseCorrelate(pair.reference, pair.next, window);
    const PhaseCorrelationResult ours = RegisterPhaseCorrelation(pair.reference, pair.next);
    // OpenCV's 5x5 centroid is exact at whole pixels and off by up to ~0.3 px between them
    // (0.18 px RMS on these pairs); ours is at least as close to the truth.
    const bool whole_pixels = shift.x == std::round(shift.x) && shift.y == std::round(shift.y);
    EXPECT_LE(Distance(ours.shift, opencv), whole_pixels ? 0.05 : 0.35) << shift << opencv;
    EXPECT_LE(Distance(ours.shift, shift), Distance(opencv, shift) + 0.01) << shift << opencv;
  }
}

TEST(PhaseCorrelation, RecoversRotation) {
  PhaseCorrelationOptions options;
  options.estimate_rotation = true;
  int seed = 100;
  for (const double angle_deg : {3.3, -6.7, 0.0, 1.5}) {
    const cv::Point2d shift(4.6, -2.3);
    const RegistrationPair pair =
        MakeRegistrationPair({256, 192}, shift, angle_deg * kDeg, 1.0, ++seed);
    const PhaseCorrelationResult result =
        RegisterPhaseCorrelation(pair.reference, pair.next, options);
    EXPECT_NEAR(result.rotation_rad / kDeg, angle_deg, 0.03);
    EXPECT_LE(Distance(result.shift, shift), 0.1) << angle_deg << result.shift;
    EXPECT_GT(result.peak, 0.2);
  }
}

// The search climbs from the prior; a prior on the wrong side of the range still ends on the
// pair's rotation, as the scan of the whole range does.
TEST(PhaseCorrelation, RotationSearchFromAFarPriorFindsTheAngle) {
  const cv::Point2d shift(-3.2, 1.7);
  const RegistrationPair pair = MakeRegistrationPair({256, 96}, shift, -6.7 * kDeg, 1.0, 31);
  PhaseCorrelationOptions options;
  options.estimate_rotation = true;
  for (const bool from_prior : {true, false}) {
    options.rotation_from_prior = from_prior;
    for (const double prior_deg : {-6.0, 0.0, 9.0}) {
      const PhaseCorrelationResult result =
          RegisterPhaseCorrelation(pair.reference, pair.next, options, prior_deg * kDeg);
      EXPECT_NEAR(result.rotation_rad / kDeg, -6.7, 0.05) << from_prior << " " << prior_deg;
      EXPECT_LE(Distance(result.shift, shift), 0.15) << from_prior << " " << prior_deg;
    }
  }
}

TEST(PhaseCorrelation, PeakMeasuresConfidence) {
  const RegistrationPair pair = MakeRegistrationPair({160, 120}, {3.0, 1.0}, 0.0, 1.0, 5);
  const RegistrationPair other = MakeRegistrationPair({160, 120}, {0.0, 0.0}, 0.0, 1.0, 6);
  const double matched = RegisterPhaseCorrelation(pair.reference, pair.next).peak;
  const double unrelated = RegisterPhaseCorrelation(pair.reference, other.next).peak;
  EXPECT_GT(matched, 0.5);
  EXPECT_LT(unrelated, 0.2);
  EXPECT_NEAR(RegisterPhaseCorrelation(pair.reference, pair.reference).peak, 1.0, 1e-3);
}

}  // namespace
}  // namespace pipescope
