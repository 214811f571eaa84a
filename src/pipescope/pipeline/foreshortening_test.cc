#include "pipescope/pipeline/foreshortening.h"

#include <gtest/gtest.h>

#include <cmath>

#include "pipescope/pipeline/dense_motion_model.h"

namespace pipescope {
namespace {

// Closed form in the cross-section: a camera at y0 = radius - d on the line to the wall, its ray
// at angle a from the optical axis, meets the wall at t = -y0 cos a + sqrt(r^2 - y0^2 sin^2 a),
// at depth t cos a.
double ClosedFormRatio(double radius, double d, double tan_a) {
  const double a = std::atan(tan_a);
  const double y0 = radius - d;
  const double t =
      -y0 * std::cos(a) + std::sqrt(radius * radius - y0 * y0 * std::sin(a) * std::sin(a));
  return d / (t * std::cos(a));
}

TEST(ForeshorteningProfile, RatiosFollowTheCircleForEveryMount) {
  const double radius = 0.0767, focal = 64.0;
  const cv::Point2d principal(63.7, 47.2);
  for (const double d : {radius, 0.05, 0.11}) {  // centred, near the wall, past the axis
    for (const std::string axis : {"x", "-y"}) {
      const bool along_x = axis == "x";
      const Eigen::Isometry3d start = MountedStartPose({axis}, radius, d);
      const cv::Rect band = along_x ? cv::Rect(0, 20, 128, 50) : cv::Rect(30, 0, 60, 96);
      const ForeshorteningProfile profile(start, radius, d, focal, principal, band, along_x);
      ASSERT_EQ(profile.ratios().size(), static_cast<std::size_t>(along_x ? 50 : 60));
      for (std::size_t i = 0; i < profile.ratios().size(); ++i) {
        const double offset =
            along_x ? (band.y + i - principal.y) / focal : (band.x + i - principal.x) / focal;
        EXPECT_NEAR(profile.ratios()[i], ClosedFormRatio(radius, d, offset), 1e-9);
        EXPECT_GE(profile.ratios()[i], 1.0 - 1e-12);  // the wall is concave
      }
    }
  }
}

TEST(ForeshorteningProfile, WeightsLinesByTheirGradientAlongThePipe) {
  const double radius = 0.0767, d = 0.06, focal = 64.0;
  const cv::Rect band(0, 0, 40, 30);
  const ForeshorteningProfile profile(MountedStartPose({"x"}, radius, d), radius, d, focal,
                                      {19.5, 14.5}, band, true);
  const std::vector<double>& ratios = profile.ratios();
  // Texture along the pipe on row 3 only: that row's ratio.
  cv::Mat one_row = cv::Mat::zeros(band.size(), CV_32F);
  for (int x = 0; x < band.width; x += 2) one_row.at<float>(3, x) = 10.0f;
  EXPECT_NEAR(profile.AxialScaleRatio(one_row), ratios[3], 1e-12);
  // Stripes across the pipe (the same in every row): the mean ratio.
  cv::Mat stripes(band.size(), CV_32F);
  for (int y = 0; y < band.height; ++y) {
    for (int x = 0; x < band.width; ++x) stripes.at<float>(y, x) = std::sin(0.7 * x);
  }
  double mean = 0.0;
  for (const double ratio : ratios) mean += ratio / ratios.size();
  EXPECT_NEAR(profile.AxialScaleRatio(stripes), mean, 1e-9);
  // Texture that varies only across the pipe has no gradient along it: no correction.
  cv::Mat across(band.size(), CV_32F);
  for (int y = 0; y < band.height; ++y) across.row(y).setTo(static_cast<float>(y % 3));
  EXPECT_DOUBLE_EQ(profile.AxialScaleRatio(across), 1.0);
}

}  // namespace
}  // namespace pipescope
