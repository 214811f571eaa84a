#include "pipescope/pipeline/wall_distance_statement.h"

#include <gtest/gtest.h>

#include <cmath>

namespace pipescope {
namespace {

Camera Pinhole(int width, int height, double fov_deg) {
  const double f = 0.5 * width / std::tan(0.5 * fov_deg * M_PI / 180.0);
  return Camera(CameraModelId::kPinholeRadtan, width, height,
                {f, f, 0.5 * (width - 1), 0.5 * (height - 1), 0, 0, 0, 0, 0});
}

TEST(WallDistanceStatement, SparseOnAWideViewMeasuresItAndSaysNothing) {
  const WallDistanceStatement statement = MakeWallDistanceStatement(
      Pinhole(1024, 768, 70), CameraMount{}, 0.07666, 0.07666, "reference_scale_px_per_m", true);
  EXPECT_TRUE(WallDistanceMeasured(statement));
  EXPECT_EQ(WallDistanceWarning(statement, "sparse"), "");
  const nlohmann::json json = WallDistanceJson(statement);
  EXPECT_TRUE(json["measured"]);
  EXPECT_TRUE(json["view_observes"]);
  EXPECT_NEAR(json["scale_error_pct_per_mm"], 100.0 * 0.001 / 0.07666, 1e-9);
}

TEST(WallDistanceStatement, SparseOnANarrowViewSaysTheScaleHoldsTheStart) {
  const WallDistanceStatement statement = MakeWallDistanceStatement(
      Pinhole(640, 480, 25), CameraMount{}, 0.19378, 0.19378, "reference_scale_px_per_m", true);
  EXPECT_FALSE(WallDistanceMeasured(statement));
  const std::string warning = WallDistanceWarning(statement, "sparse");
  EXPECT_NE(warning.find("too little of the wall's curvature"), std::string::npos) << warning;
  EXPECT_NE(warning.find("193.8 mm"), std::string::npos) << warning;
  EXPECT_NE(warning.find("0.52 % long"), std::string::npos) << warning;
}

TEST(WallDistanceStatement, DenseMethodsSayTheyAssumeItAndWhatWouldMeasureIt) {
  const WallDistanceStatement wide = MakeWallDistanceStatement(
      Pinhole(1024, 768, 70), CameraMount{}, 0.07666, 0.07666, "reference_scale_px_per_m", false);
  EXPECT_FALSE(WallDistanceMeasured(wide));
  const std::string warning = WallDistanceWarning(wide, "dense-lk");
  EXPECT_NE(warning.find("well enough to measure it"), std::string::npos) << warning;
  EXPECT_NE(warning.find("dense-unrolled where the texture allows"), std::string::npos) << warning;
  const WallDistanceStatement no_radius = MakeWallDistanceStatement(
      Pinhole(1024, 768, 70), CameraMount{}, 0.0, 0.07666, "reference_scale_px_per_m", false);
  EXPECT_FALSE(no_radius.observability.has_value());
  EXPECT_TRUE(WallDistanceJson(no_radius)["view_observes"].is_null());
  EXPECT_NE(WallDistanceWarning(no_radius, "phase").find("unknown"), std::string::npos);
}

}  // namespace
}  // namespace pipescope
