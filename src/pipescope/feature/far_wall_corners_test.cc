#include "pipescope/feature/far_wall_corners.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>
#include <random>

#include "pipescope/feature/feature_tracker.h"

namespace pipescope {
namespace {

// A textured frame (floating point, as the gain-corrected frames are) whose middle (a disk) is
// 5 times darker, as a forward fisheye sees the far wall of a lit pipe.
cv::Mat DarkMiddleFrame(cv::Point centre, int radius) {
  cv::Mat noise(480, 640, CV_32F);
  cv::randu(noise, 0.0, 255.0);
  cv::Mat texture;
  cv::GaussianBlur(noise, texture, cv::Size(0, 0), 2.0);
  cv::Mat dark(texture.size(), CV_32F, cv::Scalar(1.0f));
  cv::circle(dark, centre, radius, cv::Scalar(0.2f), cv::FILLED);
  cv::Mat frame;
  cv::multiply(texture, dark, frame);
  return frame;
}

bool Inside(const cv::Mat& mask, const cv::Point2f& point) {
  return mask.at<unsigned char>(cvRound(point.y), cvRound(point.x)) != 0;
}

// The quarters' strongest corners lie on the bright near wall; the far-wall corners fill the dark
// middle, each inside the cone, none on a corner already taken: the count asked, less the few
// the quarters took there.
TEST(FarWallCorners, FillTheDarkMiddleTheQuartersLeaveEmpty) {
  const cv::Point centre(320, 240);
  const cv::Mat frame = DarkMiddleFrame(centre, 80);
  cv::Mat cone = cv::Mat::zeros(frame.size(), CV_8U);
  cv::circle(cone, centre, 80, cv::Scalar(255), cv::FILLED);
  RegionHarrisOptions harris = FisheyeRegionHarrisOptions();
  harris.per_cell = 60;
  std::vector<cv::Point2f> existing;
  for (const Keypoint& keypoint : DetectRegionHarris(frame, harris)) {
    existing.push_back(keypoint.position);
  }
  int existing_inside = 0;
  for (const cv::Point2f& point : existing) existing_inside += Inside(cone, point) ? 1 : 0;
  EXPECT_LT(existing_inside, 5) << "of " << existing.size();

  const std::vector<cv::Point2f> far = FarWallCorners(frame, cone, harris, 50, 3.0, existing);
  EXPECT_LE(far.size(), 50u);
  EXPECT_GE(static_cast<int>(far.size()), 50 - existing_inside);
  for (const cv::Point2f& point : far) {
    EXPECT_TRUE(Inside(cone, point)) << point;
    for (const cv::Point2f& other : existing) EXPECT_GE(cv::norm(point - other), 3.0) << point;
  }
  EXPECT_TRUE(FarWallCorners(frame, cone, harris, 0, 3.0, existing).empty());
  // A corner already taken is not taken again.
  const std::vector<cv::Point2f> again = FarWallCorners(frame, cone, harris, 50, 3.0, far);
  for (const cv::Point2f& point : again) {
    for (const cv::Point2f& other : far) EXPECT_GE(cv::norm(point - other), 3.0) << point;
  }
}

}  // namespace
}  // namespace pipescope
