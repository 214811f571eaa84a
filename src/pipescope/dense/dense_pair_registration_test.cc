#include "pipescope/dense/dense_pair_registration.h"

#include <gtest/gtest.h>

#include <cmath>

#include "pipescope/dense/testing.h"
#include "pipescope/util/error.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

TEST(DenseMethod, NamesRoundTripAndUnknownNamesAreRejected) {
  for (const std::string& name : DenseMethodNames()) {
    EXPECT_EQ(DenseMethodName(ParseDenseMethod(name)), name);
  }
  EXPECT_EQ(ParseDenseMethod("dense-hybrid"), DenseMethod::kHybrid);
  const std::string message = InputErrorMessage([] { ParseDenseMethod("dense-foo"); });
  EXPECT_NE(message.find("--method"), std::string::npos);
  EXPECT_NE(message.find("dense-zncc"), std::string::npos);
}

struct MethodCase {
  DenseMethod method;
  double tolerance_px;
};

class PlanarPairRegistration : public ::testing::TestWithParam<MethodCase> {};

// A known sub-pixel shift at the quarter resolution 000 registers (160x120); the full search
// finds the nearest whole shift (within 0.5 px per axis).
TEST_P(PlanarPairRegistration, RecoversAKnownShift) {
  const cv::Point2d truth(5.37, -1.62);
  const RegistrationPair pair = MakeRegistrationPair({160, 120}, truth, 0.0, 1.0, 11);
  const PairMotion motion =
      RegisterPlanarPair(GetParam().method, pair.reference, pair.next, {}, {5.0, -1.0});
  EXPECT_TRUE(motion.failure.empty()) << motion.failure;
  EXPECT_LT(Distance(motion.shift, truth), GetParam().tolerance_px)
      << motion.shift << " vs " << truth;
  EXPECT_GT(motion.correlation, 0.8);
  EXPECT_NEAR(motion.rotation_rad, 0.0, 2e-3);
}

INSTANTIATE_TEST_SUITE_P(AllPlanarMethods, PlanarPairRegistration,
                         ::testing::Values(MethodCase{DenseMethod::kSad, 0.71},
                                           MethodCase{DenseMethod::kSsd, 0.71},
                                           MethodCase{DenseMethod::kZncc, 0.71},
                                           MethodCase{DenseMethod::kLucasKanade, 0.05},
                                           MethodCase{DenseMethod::kHybrid, 0.05},
                                           MethodCase{DenseMethod::kPhase, 0.05},
                                           MethodCase{DenseMethod::kOpenCvPhase, 0.3}),
                         [](const ::testing::TestParamInfo<MethodCase>& info) {
                           std::string name = DenseMethodName(info.param.method);
                           for (char& c : name) c = c == '-' ? '_' : c;
                           return name;
                         });

// The full search's window is centred on the prediction: a shift beyond the window around zero
// is found when the prediction is near it, and missed (flagged on the window's edge) without.
TEST(PlanarPairRegistration, FullSearchWindowFollowsThePrediction) {
  const cv::Point2d truth(41.3, -2.2);
  const RegistrationPair pair = MakeRegistrationPair({160, 120}, truth, 0.0, 1.0, 12);
  PairRegistrationOptions options;
  options.full_search.max_shift_x_px = 8;
  options.full_search.max_shift_y_px = 4;
  for (const DenseMethod method : {DenseMethod::kSad, DenseMethod::kHybrid}) {
    const PairMotion predicted =
        RegisterPlanarPair(method, pair.reference, pair.next, options, {38.6, -1.0});
    EXPECT_TRUE(predicted.failure.empty()) << predicted.failure;
    EXPECT_LT(Distance(predicted.shift, truth), method == DenseMethod::kSad ? 0.71 : 0.05)
        << predicted.shift;
    EXPECT_FALSE(predicted.still);
    const PairMotion unpredicted =
        RegisterPlanarPair(method, pair.reference, pair.next, options, {0.0, 0.0});
    EXPECT_FALSE(unpredicted.failure.empty());
  }
}

// 000 §4.2.3's hybrid keeps the full search's whole-pixel shift when the refinement is not
// accepted; the pair says so instead of passing the integer off as sub-pixel.
TEST(PlanarPairRegistration, HybridSaysWhenItKeptTheWholePixelShift) {
  const cv::Point2d truth(5.37, -1.62);
  const RegistrationPair pair = MakeRegistrationPair({160, 120}, truth, 0.0, 1.0, 11);
  const PairMotion refined =
      RegisterPlanarPair(DenseMethod::kHybrid, pair.reference, pair.next, {}, {5.0, -1.0});
  EXPECT_FALSE(refined.integer_only);
  EXPECT_LT(Distance(refined.shift, truth), 0.05) << refined.shift;
  PairRegistrationOptions options;
  options.hybrid.max_refinement_px = 0.1;  // the 0.37 px and 0.38 px corrections are rejected
  const PairMotion kept =
      RegisterPlanarPair(DenseMethod::kHybrid, pair.reference, pair.next, options, {5.0, -1.0});
  EXPECT_TRUE(kept.integer_only);
  EXPECT_TRUE(kept.failure.empty()) << kept.failure;
  EXPECT_EQ(kept.shift, cv::Point2d(5.0, -2.0));
}

// Phase correlation reports a still pair (000 §4.2.3's "keep stationary frames at zero motion")
// when the translation it finds is below still_shift_px, and a small true motion as motion.
TEST(PlanarPairRegistration, PhaseHoldsAStillPairAtZero) {
  const RegistrationPair still = MakeRegistrationPair({160, 120}, {0.0, 0.0}, 0.0, 1.0, 13);
  const PairMotion held =
      RegisterPlanarPair(DenseMethod::kPhase, still.reference, still.next, {}, {0.0, 0.0});
  EXPECT_TRUE(held.still);
  EXPECT_EQ(held.shift, cv::Point2d(0.0, 0.0));
  const RegistrationPair moved = MakeRegistrationPair({160, 120}, {0.3, 0.0}, 0.0, 1.0, 13);
  const PairMotion moving =
      RegisterPlanarPair(DenseMethod::kPhase, moved.reference, moved.next, {}, {0.0, 0.0});
  EXPECT_FALSE(moving.still);
  EXPECT_LT(Distance(moving.shift, {0.3, 0.0}), 0.05) << moving.shift;
}

TEST(PlanarPairRegistration, PhaseRecoversRotation) {
  const double rotation = 2.5 * M_PI / 180.0;
  const RegistrationPair pair = MakeRegistrationPair({256, 192}, {3.2, 1.1}, rotation, 1.0, 5);
  PairRegistrationOptions options;
  options.phase.estimate_rotation = true;
  const PairMotion motion =
      RegisterPlanarPair(DenseMethod::kPhase, pair.reference, pair.next, options, {0.0, 0.0});
  EXPECT_NEAR(motion.rotation_rad, rotation, 0.1 * M_PI / 180.0);
  EXPECT_LT(Distance(motion.shift, {3.2, 1.1}), 0.2);
}

TEST(PlanarPairRegistration, UnrelatedFramesFail) {
  const RegistrationPair a = MakeRegistrationPair({160, 120}, {0, 0}, 0.0, 1.0, 1);
  const RegistrationPair b = MakeRegistrationPair({160, 120}, {0, 0}, 0.0, 1.0, 2);
  for (DenseMethod method :
       {DenseMethod::kSad, DenseMethod::kHybrid, DenseMethod::kPhase, DenseMethod::kLucasKanade}) {
    const PairMotion motion = RegisterPlanarPair(method, a.reference, b.next, {}, {0.0, 0.0});
    EXPECT_FALSE(motion.failure.empty()) << DenseMethodName(method);
    EXPECT_LT(motion.correlation, 0.3);
  }
}

TEST(PlanarPairRegistration, TextureLessFramesFail) {
  cv::Mat flat_a(120, 160, CV_32F), flat_b(120, 160, CV_32F);
  cv::RNG rng(3);
  rng.fill(flat_a, cv::RNG::NORMAL, 100.0, 1.0);
  rng.fill(flat_b, cv::RNG::NORMAL, 100.0, 1.0);
  const PairMotion motion =
      RegisterPlanarPair(DenseMethod::kHybrid, flat_a, flat_b, {}, {0.0, 0.0});
  EXPECT_FALSE(motion.failure.empty());
}

TEST(OverlapCorrelation, IsOneForExactlyShiftedContentAndMatchesANaiveZncc) {
  cv::Mat big(140, 200, CV_32F);
  cv::RNG rng(9);
  rng.fill(big, cv::RNG::UNIFORM, 0.0, 255.0);
  const cv::Mat reference = big(cv::Rect(10, 10, 160, 120)).clone();
  const cv::Mat next = big(cv::Rect(7, 14, 160, 120)).clone();  // content moves by (3, -4)
  EXPECT_NEAR(OverlapCorrelation(reference, next, {3.0, -4.0}), 1.0, 1e-5);
  // Naive ZNCC at a wrong shift.
  const cv::Point t(1, 0);
  double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0, n = 0;
  for (int y = 0; y < 120; ++y) {
    for (int x = 0; x + t.x < 160; ++x) {
      const double a = reference.at<float>(y, x), b = next.at<float>(y, x + t.x);
      sa += a, sb += b, saa += a * a, sbb += b * b, sab += a * b, ++n;
    }
  }
  const double covariance = sab - sa * sb / n;
  const double naive = covariance / std::sqrt((saa - sa * sa / n) * (sbb - sb * sb / n));
  EXPECT_NEAR(OverlapCorrelation(reference, next, {1.0, 0.0}), naive, 1e-4);
}

// A uniform overlap (a black frame, a lens cap) correlates with nothing: cv::matchTemplate alone
// scores a constant template 1, and a black frame passed as registered.
TEST(OverlapCorrelation, IsZeroForAUniformOverlap) {
  cv::Mat textured(120, 160, CV_32F);
  cv::RNG rng(10);
  rng.fill(textured, cv::RNG::UNIFORM, 0.0, 255.0);
  const cv::Mat black = cv::Mat::zeros(textured.size(), CV_32F);
  EXPECT_EQ(OverlapCorrelation(textured, black, {2.0, 1.0}), 0.0);
  EXPECT_EQ(OverlapCorrelation(black, textured, {2.0, 1.0}), 0.0);
  EXPECT_EQ(OverlapCorrelation(black, black, {0.0, 0.0}), 0.0);
}

}  // namespace
}  // namespace pipescope
