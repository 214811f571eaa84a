#include "pipescope/mapping/image_mosaic.h"

#include <gtest/gtest.h>

#include <cmath>

#include "pipescope/image/undistortion.h"
#include "pipescope/image/unrolling_testing.h"

namespace pipescope {
namespace {

TEST(ImageMosaic, RebuildsTheImageItWasCutFrom) {
  cv::Mat big(260, 1200, CV_32F);
  cv::RNG rng(7);
  rng.fill(big, cv::RNG::UNIFORM, 0.0, 255.0);
  ImageMosaic mosaic(50.0);
  const cv::Size frame_size(200, 150);
  cv::Rect covered;
  for (int k = 0; k < 12; ++k) {
    const cv::Point offset(80 * k, (k * 37) % 100);
    ASSERT_TRUE(mosaic.Add(big(cv::Rect(offset, frame_size)).clone(), offset));
    covered = k == 0 ? cv::Rect(offset, frame_size) : covered | cv::Rect(offset, frame_size);
  }
  EXPECT_EQ(mosaic.frames_used(), 12);
  ASSERT_EQ(mosaic.Bounds(), covered);
  const cv::Mat rendered = mosaic.Render();
  ASSERT_EQ(rendered.size(), covered.size());
  int compared = 0;
  for (int y = 0; y < rendered.rows; ++y) {
    for (int x = 0; x < rendered.cols; ++x) {
      const cv::Point cell = cv::Point(x, y) + covered.tl();
      bool seen = false;
      for (int k = 0; k < 12; ++k) {
        seen |= cv::Rect(cv::Point(80 * k, (k * 37) % 100), frame_size).contains(cell);
      }
      const float value = rendered.at<float>(y, x);
      if (seen) {
        ++compared;
        ASSERT_NEAR(value, big.at<float>(cell), 1e-4f) << cell;
      } else {
        ASSERT_TRUE(std::isnan(value)) << cell;
      }
    }
  }
  EXPECT_GT(compared, 150000);
}

TEST(ImageMosaic, SubPixelOffsetsResampleBilinearly) {
  // Frames of a plane f(x, y) = 0.5 x - 0.25 y + 3 taken at fractional offsets: bilinear
  // resampling is exact for a plane, so the mosaic is the plane where covered.
  const auto plane = [](double x, double y) { return 0.5 * x - 0.25 * y + 3.0; };
  ImageMosaic mosaic(10.0);
  const cv::Point2d offsets[] = {{-5.3, 2.7}, {20.25, -1.5}, {41.9, 0.0}, {60.0, 3.125}};
  for (const cv::Point2d& offset : offsets) {
    cv::Mat frame(30, 40, CV_32F);
    for (int y = 0; y < frame.rows; ++y) {
      for (int x = 0; x < frame.cols; ++x) {
        frame.at<float>(y, x) = static_cast<float>(plane(x + offset.x, y + offset.y));
      }
    }
    ASSERT_TRUE(mosaic.Add(frame, offset));
  }
  // The union of [offset, offset + size - 1] over the frames, rounded inwards.
  EXPECT_EQ(mosaic.Bounds(), cv::Rect(-5, -1, 60 + 40 - 1 - (-5) + 1, 3 + 30 - 1 - (-1) + 1));
  const cv::Mat rendered = mosaic.Render();
  const cv::Point origin = mosaic.Bounds().tl();
  int compared = 0;
  for (int y = 0; y < rendered.rows; ++y) {
    for (int x = 0; x < rendered.cols; ++x) {
      const float value = rendered.at<float>(y, x);
      if (std::isnan(value)) continue;
      ++compared;
      ASSERT_NEAR(value, plane(x + origin.x, y + origin.y), 1e-4);
    }
  }
  EXPECT_GT(compared, 3000);
}

TEST(ImageMosaic, SkipsFramesCloserThanTheSpacing) {
  ImageMosaic mosaic;  // 50 px, 000 §6.1
  const cv::Mat ones(20, 20, CV_32F, cv::Scalar(1.0f));
  const cv::Mat nines(20, 20, CV_32F, cv::Scalar(9.0f));
  EXPECT_TRUE(mosaic.Add(ones, {0, 0}));
  EXPECT_FALSE(mosaic.Add(nines, {30, 0}));
  EXPECT_FALSE(mosaic.Add(nines, {49.9, 0}));
  EXPECT_FALSE(mosaic.Add(nines, {30, 40 - 1e-9}));  // 49.999... px away
  EXPECT_TRUE(mosaic.Add(ones, {50, 0}));
  EXPECT_FALSE(mosaic.Add(nines, {50, 49}));  // measured from the last frame used
  EXPECT_TRUE(mosaic.Add(ones, {80, 40}));
  EXPECT_EQ(mosaic.frames_used(), 3);
  const cv::Mat rendered = mosaic.Render();
  cv::Mat finite = rendered == rendered;  // NaN != NaN
  EXPECT_EQ(cv::countNonZero(finite), 3 * 400);
  EXPECT_EQ(cv::countNonZero(rendered == 1.0f), 3 * 400);  // no skipped frame leaked in
}

TEST(ImageMosaic, LeavesMaskedPixelsOut) {
  ImageMosaic mosaic(0.0);
  cv::Mat frame(10, 10, CV_32F, cv::Scalar(4.0f));
  cv::Mat mask(10, 10, CV_8U, cv::Scalar(255));
  mask(cv::Rect(0, 0, 5, 10)) = 0;
  ASSERT_TRUE(mosaic.Add(frame, {0.5, 0}, mask));
  // Cell x samples frame x - 0.5: valid when both taps x - 1 and x are unmasked, x in [6, 9].
  EXPECT_EQ(mosaic.Bounds(), cv::Rect(6, 0, 4, 10));
  EXPECT_EQ(cv::countNonZero(mosaic.Render() == 4.0f), 40);
}

TEST(ImageOffsetFromPoses, ClosedForm) {
  Eigen::Isometry3d first = Eigen::Isometry3d::Identity();
  first.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).matrix();
  first.translation() = Eigen::Vector3d(0.1, -0.2, 0.5);
  Eigen::Isometry3d moved = first;
  moved.translation() += first.linear() * Eigen::Vector3d(0.01, -0.002, 0.3);
  const cv::Point2d offset = ImageOffsetFromPoses(first, moved, 1000.0);
  EXPECT_NEAR(offset.x, 10.0, 1e-9);
  EXPECT_NEAR(offset.y, -2.0, 1e-9);
}

// Undistorted simulator frames placed at the offsets their true poses imply line up: the sign
// and size of the offset are right.
TEST(ImageOffsetFromPoses, AlignsSimulatedFrames) {
  SimulationConfig config = SmallSteelConfig();
  config.lateral_offset_m = 0.0;  // keep the wall at the reference distance
  config.wobble_deg = 0.0;
  config.roll_deg = 0.0;
  const Simulation simulation(config);
  const GainCorrectedFrames frames(simulation);
  const Undistorter undistorter(simulation.camera());
  const double zeta = CentralFocalLengthPx(simulation.camera()) / config.radius_m;
  const int k = 8;
  const cv::Point2d offset =
      ImageOffsetFromPoses(simulation.FramePose(0), simulation.FramePose(k), zeta);
  ASSERT_GT(offset.x, 40.0);  // moved along the pipe, image x
  // Rectified pixels whose ray the lens does not see are 0: leave them out.
  const cv::Mat seen =
      undistorter.Apply(cv::Mat(config.height, config.width, CV_32F, cv::Scalar(1.0f))) > 0.999f;
  const auto overlap_zncc = [&](const cv::Point2d& placed) {
    ImageMosaic first(0.0), second(0.0);
    first.Add(undistorter.Apply(frames.Frame(0)), {0, 0}, seen);
    second.Add(undistorter.Apply(frames.Frame(k)), placed, seen);
    const cv::Rect common = first.Bounds() & second.Bounds();
    const cv::Mat a = first.Render()(common - first.Bounds().tl());
    const cv::Mat b = second.Render()(common - second.Bounds().tl());
    return MaskedHighPassZncc(a, b, (a == a) & (b == b));
  };
  // Not 1: the perspective image of a cylinder is not a pure translation (000 §6.1 on
  // foreshortening).
  EXPECT_GT(overlap_zncc(offset), 0.85);
  EXPECT_LT(overlap_zncc(-offset), 0.5);
  EXPECT_LT(overlap_zncc(offset + cv::Point2d(4, 0)), 0.5);
}

}  // namespace
}  // namespace pipescope
