#include "pipescope/pipeline/travel_direction.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "pipescope/camera/camera_io.h"
#include "pipescope/image/gain_mask.h"
#include "pipescope/io/dataset.h"
#include "pipescope/io/trajectory.h"
#include "pipescope/synthetic/dataset_writer.h"
#include "pipescope/synthetic/presets.h"
#include "pipescope/synthetic/simulation_config.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

struct Measured {
  TravelDirection travel;
  Eigen::Vector3d truth;  // the true displacement's direction, in the reference camera's frame
};

// Simulates `preset` small and measures the direction of travel over its first frames.
Measured MeasureOn(const std::string& preset, double speed_m_s) {
  const auto dir = MakeTestDirectory("travel_direction") / preset;
  SimulationConfig config = PresetConfig(preset);
  config.width = 320;
  config.height = 240;
  config.frames = 30;
  config.speed_m_s = speed_m_s;
  config.out_and_back = false;
  SimulateDataset(config, dir);
  const DatasetManifest manifest = OpenDataset(dir);
  const Camera camera = ReadCamera(manifest.camera_path);
  const cv::Mat gain_mask =
      ReadDatasetGainMask(manifest.gain_mask_path, camera.Width(), camera.Height());
  Measured measured;
  measured.travel = MeasureTravelDirection(manifest, camera, gain_mask, cv::Mat(),
                                           KltTrackerOptions{}, TravelDirectionOptions{});
  const Trajectory truth = ReadTumTrajectory(manifest.groundtruth_path);
  if (measured.travel.found) {
    const StampedPose& from = truth[measured.travel.reference_frame];
    const StampedPose& to = truth[measured.travel.frame];
    measured.truth = (from.rotation.conjugate() * (to.position - from.position)).normalized();
  }
  return measured;
}

double AngleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.dot(b), -1.0, 1.0)) * 180.0 / M_PI;
}

// 000's wall camera: the crawler moves along image x, across the optical axis. At this size the
// direction comes out a few degrees off the truth (a view's translation across it against a
// turn), well within the 30 degrees by which the filter takes it to be image x.
TEST(MeasureTravelDirection, FindsAWallCameraMovingAcrossItsView) {
  const Measured measured = MeasureOn("steel-6in", 0.03);
  ASSERT_TRUE(measured.travel.found) << measured.travel.failure;
  EXPECT_LT(AngleDeg(measured.travel.direction, measured.truth), 7.0)
      << measured.travel.direction.transpose() << " truth " << measured.truth.transpose();
  EXPECT_GT(std::abs(measured.travel.direction.x()), std::cos(10.0 * M_PI / 180.0));
  EXPECT_GT(measured.travel.inliers, 30);
}

// 004's camera looking down the tube: the crawler moves along the optical axis.
TEST(MeasureTravelDirection, FindsACameraLookingDownTheTube) {
  const Measured measured = MeasureOn("tube-bend", 0.1);
  ASSERT_TRUE(measured.travel.found) << measured.travel.failure;
  EXPECT_LT(AngleDeg(measured.travel.direction, measured.truth), 6.0)
      << measured.travel.direction.transpose() << " truth " << measured.truth.transpose();
  EXPECT_GT(std::abs(measured.travel.direction.z()), 0.9);
}

// A crawler that does not move shows no direction, and says why.
TEST(MeasureTravelDirection, SaysSoWhenTheCameraStandsStill) {
  const Measured measured = MeasureOn("steel-6in", 0.0);
  EXPECT_FALSE(measured.travel.found);
  EXPECT_NE(measured.travel.failure.find("did not turn"), std::string::npos)
      << measured.travel.failure;
}

}  // namespace
}  // namespace pipescope
