#include "pipescope/image/undistortion.h"

#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace pipescope {
namespace {

// OpenCV's own rectification maps are the oracle for the two models OpenCV implements.
TEST(Undistorter, MatchesOpenCvForPinholeRadtan) {
  const Camera camera(CameraModelId::kPinholeRadtan, 320, 240,
                      {300.0, 302.0, 161.3, 118.7, -0.21, 0.06, 4e-4, -3e-4, 0.01});
  const Undistorter undistorter(camera);
  const cv::Matx33d k(300.0, 0, 161.3, 0, 302.0, 118.7, 0, 0, 1);
  const cv::Matx33d new_k(300.0, 0, 161.3, 0, 300.0, 118.7, 0, 0, 1);
  const std::vector<double> distortion = {-0.21, 0.06, 4e-4, -3e-4, 0.01};
  cv::Mat map_x, map_y;
  cv::initUndistortRectifyMap(k, distortion, cv::Matx33d::eye(), new_k, cv::Size(320, 240),
                              CV_32FC1, map_x, map_y);
  for (int y = 0; y < 240; y += 7) {
    for (int x = 0; x < 320; x += 7) {
      const cv::Point2f ours = undistorter.SourcePixel(x, y);
      EXPECT_NEAR(ours.x, map_x.at<float>(y, x), 2e-3) << x << "," << y;
      EXPECT_NEAR(ours.y, map_y.at<float>(y, x), 2e-3) << x << "," << y;
    }
  }
  EXPECT_DOUBLE_EQ(undistorter.rectified_camera().Params()[0], 300.0);
}

TEST(Undistorter, MatchesOpenCvForKannalaBrandt) {
  const Camera camera(CameraModelId::kKannalaBrandt, 320, 240,
                      {200.0, 201.0, 159.5, 120.5, 0.02, -0.01, 0.003, -0.001});
  const Undistorter undistorter(camera);
  const cv::Matx33d k(200.0, 0, 159.5, 0, 201.0, 120.5, 0, 0, 1);
  const cv::Matx33d new_k(200.0, 0, 159.5, 0, 200.0, 120.5, 0, 0, 1);
  cv::Mat map_x, map_y;
  cv::fisheye::initUndistortRectifyMap(k, cv::Vec4d(0.02, -0.01, 0.003, -0.001), cv::Matx33d::eye(),
                                       new_k, cv::Size(320, 240), CV_32FC1, map_x, map_y);
  for (int y = 0; y < 240; y += 7) {
    for (int x = 0; x < 320; x += 7) {
      const cv::Point2f ours = undistorter.SourcePixel(x, y);
      EXPECT_NEAR(ours.x, map_x.at<float>(y, x), 2e-3) << x << "," << y;
      EXPECT_NEAR(ours.y, map_y.at<float>(y, x), 2e-3) << x << "," << y;
    }
  }
}

TEST(Undistorter, FisheyePolyRectifiedPixelsSeeTheirPerspectiveRays) {
  const Camera camera(CameraModelId::kFisheyePoly, 640, 480,
                      {300.0, -6.0, 0.5, -0.1, 321.0, 238.0});
  const Undistorter undistorter(camera);
  // The rectified image is a pinhole with f = k1 at the same principal point.
  const std::vector<double>& rectified = undistorter.rectified_camera().Params();
  EXPECT_EQ(rectified[0], 300.0);
  EXPECT_EQ(rectified[2], 321.0);
  for (int y = 0; y < 480; y += 11) {
    for (int x = 0; x < 640; x += 11) {
      const cv::Point2f source = undistorter.SourcePixel(x, y);
      if (source.x < 0) continue;
      Eigen::Vector3d bearing;
      ASSERT_TRUE(camera.Unproject(Eigen::Vector2d(source.x, source.y), &bearing));
      const Eigen::Vector3d ray =
          Eigen::Vector3d((x - 321.0) / 300.0, (y - 238.0) / 300.0, 1.0).normalized();
      EXPECT_NEAR((bearing - ray).norm(), 0.0, 1e-5);  // float maps: ~1e-4 px
    }
  }
}

TEST(Undistorter, ApplyResamplesThroughTheMaps) {
  const Camera camera(CameraModelId::kPinholeRadtan, 160, 120,
                      {150.0, 150.0, 79.5, 59.5, -0.15, 0.02, 0.0, 0.0, 0.0});
  const Undistorter undistorter(camera);
  // On a ramp equal to the x coordinate, bilinear sampling returns the source x of the map, to
  // the 1/32 px to which cv::remap quantises its interpolation weights.
  cv::Mat ramp(120, 160, CV_32F);
  for (int y = 0; y < 120; ++y) {
    for (int x = 0; x < 160; ++x) ramp.at<float>(y, x) = static_cast<float>(x);
  }
  const cv::Mat rectified = undistorter.Apply(ramp);
  for (int y = 10; y < 110; y += 9) {
    for (int x = 10; x < 150; x += 9) {
      const cv::Point2f source = undistorter.SourcePixel(x, y);
      if (source.x < 0 || source.x > 159 || source.y < 0 || source.y > 119) continue;
      EXPECT_NEAR(rectified.at<float>(y, x), source.x, 1.0 / 32.0 + 1e-3);
    }
  }
}

TEST(Undistorter, FixedPointTablesEqualTheFloatTables) {
  const Camera camera(CameraModelId::kKannalaBrandt, 200, 150,
                      {160.0, 160.0, 99.0, 76.0, 0.05, -0.02, 0.01, 0.0});
  const Undistorter undistorter(camera);
  cv::Mat map_x(150, 200, CV_32F), map_y(150, 200, CV_32F);
  for (int y = 0; y < 150; ++y) {
    for (int x = 0; x < 200; ++x) {
      const cv::Point2f source = undistorter.SourcePixel(x, y);
      map_x.at<float>(y, x) = source.x;
      map_y.at<float>(y, x) = source.y;
    }
  }
  cv::Mat image(150, 200, CV_8U);
  cv::randu(image, 0, 256);
  for (const int depth : {CV_8U, CV_32F}) {
    cv::Mat input;
    image.convertTo(input, depth);
    cv::Mat expected;
    cv::remap(input, expected, map_x, map_y, cv::INTER_LINEAR, cv::BORDER_CONSTANT, 0);
    const cv::Mat rectified = undistorter.Apply(input);
    EXPECT_EQ(rectified.depth(), depth);
    EXPECT_LE(cv::norm(rectified, expected, cv::NORM_INF), 1e-3) << "depth " << depth;
  }
}

}  // namespace
}  // namespace pipescope
