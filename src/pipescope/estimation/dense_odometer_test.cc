// DenseOdometer on synthetic frames: a smoothed random texture seen by an undistorted pinhole
// camera that looks at a plane and moves a known sub-pixel distance along its x axis (the pipe's
// axis for the default mount) between frames. Each method must integrate that motion in metres
// (000 eq. 18-19) and bridge a frame it cannot register.
#include "pipescope/estimation/dense_odometer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "pipescope/util/error.h"

namespace pipescope {
namespace {

constexpr int kWidth = 320, kHeight = 240;
constexpr double kZeta = 5000.0;         // pixels per metre of the wall the camera faces
constexpr double kPixelsPerFrame = 3.3;  // the wall's image motion, full-resolution pixels

Camera PlaneCamera() {
  return Camera(CameraModelId::kPinholeRadtan, kWidth, kHeight,
                {300.0, 300.0, 159.5, 119.5, 0.0, 0.0, 0.0, 0.0, 0.0});
}

// A texture with detail on several scales, wide enough for the whole run.
cv::Mat WallTexture() {
  cv::Mat noise(kHeight + 40, 1200, CV_32F);
  cv::RNG rng(5);
  rng.fill(noise, cv::RNG::UNIFORM, 0.0, 255.0);
  cv::Mat fine, coarse;
  cv::GaussianBlur(noise, fine, cv::Size(), 2.0);
  cv::GaussianBlur(noise, coarse, cv::Size(), 8.0);
  cv::Mat texture = 128.0 + 2.5 * (fine - 128.0) + 4.0 * (coarse - 128.0);
  return texture;
}

// Frame k: the texture at x + k * kPixelsPerFrame (the camera moved that far along its +x), as
// an 8-bit frame.
Frame RenderFrame(const cv::Mat& texture, int k) {
  const double offset = 20.0 + k * kPixelsPerFrame;
  const cv::Mat warp = (cv::Mat_<double>(2, 3) << 1, 0, offset, 0, 1, 20);
  cv::Mat sampled;
  cv::warpAffine(texture, sampled, warp, cv::Size(kWidth, kHeight),
                 cv::INTER_CUBIC | cv::WARP_INVERSE_MAP);
  Frame frame;
  frame.index = static_cast<std::size_t>(k);
  frame.timestamp = k / 30.0;
  frame.name = "frame " + std::to_string(k);
  sampled.convertTo(frame.grey, CV_8U);
  return frame;
}

DenseOdometerOptions OptionsFor(DenseMethod method) {
  DenseOdometerOptions options;
  options.method = method;
  options.frames.downsample = 2;
  options.registration_band = 1.0;
  return options;
}

class DenseOdometerMethods : public testing::TestWithParam<DenseMethod> {};

TEST_P(DenseOdometerMethods, IntegratesTheImageMotionInMetres) {
  // The integer searches' shifts are whole prepared pixels (2 full-resolution pixels) until
  // their key frame's rounding is carried; the sub-pixel methods are held to 0.3 px.
  const bool integer_search = GetParam() == DenseMethod::kSad || GetParam() == DenseMethod::kZncc;
  const double tolerance_px = integer_search ? 1.05 : 0.3;
  const cv::Mat texture = WallTexture();
  DenseOdometer odometer(PlaneCamera(), cv::Mat(), kZeta, 0.0, OptionsFor(GetParam()));
  constexpr int kFrames = 40;
  int key_frames = 0;
  double start_z = 0.0;
  for (int k = 0; k < kFrames; ++k) {
    const DenseOdometerStep step = odometer.Step(RenderFrame(texture, k));
    EXPECT_TRUE(step.record.failure.empty()) << k << ": " << step.record.failure;
    EXPECT_FALSE(step.failed_pair);
    if (step.record.key_frame) ++key_frames;
    if (k == 0) {
      start_z = step.world_from_cam.translation().z();
      EXPECT_TRUE(step.record.key_frame);
      continue;
    }
    // The camera moved k * 3.3 px / zeta along its x axis, the pipe's +Z for the default mount,
    // and nowhere else.
    const Eigen::Vector3d moved =
        step.world_from_cam.translation() - Eigen::Vector3d(0, 0, start_z);
    EXPECT_NEAR(moved.z(), k * kPixelsPerFrame / kZeta, tolerance_px / kZeta) << k;
    EXPECT_NEAR(moved.head<2>().norm(), 0.0, tolerance_px / kZeta) << k;
    // Prepared pixels, from the frame before.
    EXPECT_NEAR(step.record.shift.x, -kPixelsPerFrame / 2.0, tolerance_px) << k;
  }
  // Frames are registered to key frames (every 0.4 of the frame for the integer searches, 0.1
  // for the others), not to the frame before.
  EXPECT_GE(key_frames, integer_search ? 1 : 3);
  EXPECT_LE(key_frames, kFrames / 3);
}

INSTANTIATE_TEST_SUITE_P(Methods, DenseOdometerMethods,
                         testing::Values(DenseMethod::kSad, DenseMethod::kZncc,
                                         DenseMethod::kLucasKanade, DenseMethod::kHybrid,
                                         DenseMethod::kPhase),
                         [](const testing::TestParamInfo<DenseMethod>& info) {
                           std::string name = DenseMethodName(info.param);
                           for (char& c : name) {
                             if (c == '-') c = '_';
                           }
                           return name;
                         });

TEST(DenseOdometer, ASaturatedFrameIsPredictedAndTheNextRegistersToTheSameKey) {
  const cv::Mat texture = WallTexture();
  DenseOdometer odometer(PlaneCamera(), cv::Mat(), kZeta, 0.0, OptionsFor(DenseMethod::kHybrid));
  double start_z = 0.0;
  for (int k = 0; k < 14; ++k) {
    Frame frame = RenderFrame(texture, k);
    if (k == 7) frame.grey.setTo(255);
    const DenseOdometerStep step = odometer.Step(frame);
    if (k == 0) start_z = step.world_from_cam.translation().z();
    const double moved = step.world_from_cam.translation().z() - start_z;
    if (k == 7) {
      EXPECT_TRUE(step.failed_pair);
      EXPECT_NE(step.record.failure.find("saturated"), std::string::npos) << step.record.failure;
      EXPECT_FALSE(step.record.key_frame);
      // Constant velocity bridges it.
      EXPECT_NEAR(moved, k * kPixelsPerFrame / kZeta, 0.5 / kZeta);
    } else {
      EXPECT_FALSE(step.failed_pair) << k;
      EXPECT_NEAR(moved, k * kPixelsPerFrame / kZeta, 0.3 / kZeta) << k;
    }
  }
}

TEST(DenseOdometer, DenseUnrolledNeedsTheRadius) {
  EXPECT_THROW(
      DenseOdometer(PlaneCamera(), cv::Mat(), kZeta, 0.0, OptionsFor(DenseMethod::kUnrolled)),
      InputError);
}

}  // namespace
}  // namespace pipescope
