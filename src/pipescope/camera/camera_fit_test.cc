#include "pipescope/camera/camera_fit.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

namespace pipescope {
namespace {

// r = k1 theta + k2 theta^3 is Kannala-Brandt with f = k1 and k1' = k2 / k1 exactly (the
// fiberglass-network preset's lens, 190 degrees).
TEST(FitKannalaBrandt, OddCubicFisheyePolyIsRecoveredInClosedForm) {
  const Camera source(CameraModelId::kFisheyePoly, 1280, 960,
                      {291.72458689307223, -2.9172458689307228, 0, 0, 639.5, 479.5});
  const KannalaBrandtFit fit = FitKannalaBrandt(source);
  const std::vector<double>& p = fit.camera.Params();
  EXPECT_EQ(fit.camera.ModelId(), CameraModelId::kKannalaBrandt);
  EXPECT_EQ(fit.camera.Width(), 1280);
  EXPECT_EQ(fit.camera.Height(), 960);
  EXPECT_NEAR(p[0], 291.72458689307223, 1e-6);
  EXPECT_NEAR(p[1], 291.72458689307223, 1e-6);
  EXPECT_NEAR(p[2], 639.5, 1e-6);
  EXPECT_NEAR(p[3], 479.5, 1e-6);
  EXPECT_NEAR(p[4], -0.01, 1e-8);
  for (int i = 5; i < 8; ++i) EXPECT_NEAR(p[i], 0, 1e-8) << i;
  EXPECT_LT(fit.max_px, 1e-6);
  EXPECT_EQ(fit.num_samples, 200 * 16);
}

TEST(FitKannalaBrandt, KannalaBrandtSourceIsRecovered) {
  const std::vector<double> params = {400.0, 395.0, 640.2, 478.9, 0.02, -0.01, 0.003, -0.0004};
  const Camera source(CameraModelId::kKannalaBrandt, 1280, 960, params);
  KannalaBrandtFitOptions options;
  options.max_angle = 80.0 * M_PI / 180.0;
  const KannalaBrandtFit fit = FitKannalaBrandt(source, options);
  for (int i = 0; i < 8; ++i) EXPECT_NEAR(fit.camera.Params()[i], params[i], 1e-6) << i;
  EXPECT_LT(fit.rms_px, 1e-6);
}

// A theta^4 term has no odd-power counterpart: the fit is approximate, and its error grows
// with the fitted range.
TEST(FitKannalaBrandt, EvenPowerTermLeavesAResidualThatGrowsWithTheRange) {
  const Camera source(CameraModelId::kFisheyePoly, 1280, 960,
                      {300.0, -4.0, 2.0, -0.5, 639.5, 479.5});
  KannalaBrandtFitOptions narrow;
  narrow.max_angle = 45.0 * M_PI / 180.0;
  const KannalaBrandtFit narrow_fit = FitKannalaBrandt(source, narrow);
  const KannalaBrandtFit wide_fit = FitKannalaBrandt(source);
  EXPECT_GT(wide_fit.rms_px, 1e-4);
  EXPECT_LT(narrow_fit.rms_px, wide_fit.rms_px);
  EXPECT_LT(wide_fit.max_px, 1.0);
}

TEST(FitKannalaBrandt, RejectsRangesKannalaBrandtCannotHold) {
  const Camera source(CameraModelId::kFisheyePoly, 1280, 960, {300.0, -3.0, 0, 0, 639.5, 479.5});
  KannalaBrandtFitOptions options;
  options.max_angle = M_PI / 2;
  EXPECT_THROW(FitKannalaBrandt(source, options), std::invalid_argument);
  options.max_angle = 0;
  EXPECT_THROW(FitKannalaBrandt(source, options), std::invalid_argument);
}

}  // namespace
}  // namespace pipescope
