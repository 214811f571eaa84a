#include "pipescope/fisheye/guided_zncc.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

namespace pipescope {
namespace {

TEST(GuidedZncc, FindsTheBestPlaceOfOpenCvsNormalisedCorrelation) {
  // With an epipolar threshold every bearing passes, the guided search is a plain ZNCC search
  // over its box: its best pixel and score must be those of cv::matchTemplate
  // (TM_CCOEFF_NORMED) over the same box, the independent oracle.
  const Camera camera(CameraModelId::kFisheyePoly, 320, 240, {90.0, -1.0, 0.0, 0.0, 159.5, 119.5});
  const BearingTable bearings(camera);
  cv::Mat noise(240, 320, CV_32F);
  cv::randu(noise, 0.0, 255.0);
  cv::Mat grey_i;
  cv::GaussianBlur(noise, grey_i, cv::Size(5, 5), 1.5);
  cv::Mat grey_j;
  const cv::Mat shift = (cv::Mat_<double>(2, 3) << 1, 0, 4, 0, 1, -3);
  cv::warpAffine(grey_i, grey_j, shift, grey_i.size(), cv::INTER_LINEAR);
  cv::Mat disturbance(240, 320, CV_32F);
  cv::randn(disturbance, 0.0, 8.0);
  grey_j += disturbance;

  GuidedZnccOptions options;
  options.epipolar_threshold = 10.0;
  options.search_radius_px = 12;
  options.min_zncc = 0.0;
  const cv::Point2f point_i(150.f, 110.f);
  Eigen::Vector3d bearing_i;
  ASSERT_TRUE(camera.Unproject(Eigen::Vector2d(point_i.x, point_i.y), &bearing_i));
  const GuidedMatch match = GuidedZnccSearch(grey_i, grey_j, point_i, bearing_i,
                                             Eigen::Matrix3d::Identity(), bearings, options);
  ASSERT_TRUE(match.found);

  const int half = options.template_size_px / 2;
  const int r = options.search_radius_px;
  const cv::Mat templ = grey_i(cv::Rect(150 - half, 110 - half, 2 * half + 1, 2 * half + 1));
  const cv::Mat box =
      grey_j(cv::Rect(150 - r - half, 110 - r - half, 2 * r + 2 * half + 1, 2 * r + 2 * half + 1));
  cv::Mat scores;
  cv::matchTemplate(box, templ, scores, cv::TM_CCOEFF_NORMED);
  double best;
  cv::Point best_at;
  cv::minMaxLoc(scores, nullptr, &best, nullptr, &best_at);
  EXPECT_EQ(std::lround(match.point_j.x), 150 - r + best_at.x);
  EXPECT_EQ(std::lround(match.point_j.y), 110 - r + best_at.y);
  EXPECT_NEAR(match.zncc, best, 1e-4);
  // And that is the true shift.
  EXPECT_NEAR(match.point_j.x, 154.f, 0.5f);
  EXPECT_NEAR(match.point_j.y, 107.f, 0.5f);
}

}  // namespace
}  // namespace pipescope
