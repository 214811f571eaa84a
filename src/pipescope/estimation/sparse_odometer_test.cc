// SparseOdometer on synthetic tracks: a wall-looking pinhole camera (000 Fig. 3) moves down a
// pipe of known radius; its features are projections of points on the wall, matched across
// frames by the point they see. The back end alone (no images, no RANSAC) must recover the
// travel along the axis (000 §5.3).
#include "pipescope/estimation/sparse_odometer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "pipescope/geometry/camera_mount.h"

namespace pipescope {
namespace {

constexpr double kRadius = 0.0766;      // steel-6in
constexpr double kWallDistance = 0.05;  // start camera to the wall it faces
constexpr double kStep = 0.0008;        // travel a frame along the axis
constexpr int kFramesPerKeyFrame = 6;   // the caller's key-frame span

class SparseOdometerTest : public testing::Test {
 protected:
  SparseOdometerTest()
      : camera_(CameraModelId::kPinholeRadtan, 640, 480,
                {500.0, 500.0, 319.5, 239.5, 0.0, 0.0, 0.0, 0.0, 0.0}),
        start_(MountedStartPose(CameraMount{}, kRadius, kWallDistance)) {
    // Points on the wall the camera faces (phi near 90 degrees), along the whole run.
    std::mt19937 random(3);
    std::uniform_real_distribution<double> phi(M_PI / 2 - 0.6, M_PI / 2 + 0.6);
    std::uniform_real_distribution<double> along(-0.05, 0.15);
    for (int i = 0; i < 6000; ++i) {
      const double angle = phi(random);
      wall_points_.emplace_back(kRadius * std::cos(angle), kRadius * std::sin(angle),
                                along(random));
    }
    features_options_.key_frames.min_correspondences = 6;
    options_.revisit = false;                         // needs descriptors
    options_.window.hold_first_cross_section = true;  // the start is measured
    options_.window.cross_section_anchor_xy = start_.translation().head<2>();
  }

  Eigen::Isometry3d TruePose(int frame) const {
    Eigen::Isometry3d pose = start_;
    pose.translation().z() += kStep * frame;
    return pose;
  }

  // Frame `frame`'s features: every wall point it sees, with `noise_px` of pixel noise; the
  // point's index in `seen`.
  FrameFeatures Features(int frame, double noise_px, std::vector<int>* seen) {
    FrameFeatures features;
    seen->clear();
    const Eigen::Isometry3d cam_from_world = TruePose(frame).inverse();
    std::normal_distribution<double> noise(0.0, noise_px);
    for (std::size_t i = 0; i < wall_points_.size(); ++i) {
      Eigen::Vector2d pixel;
      if (camera_.Project(cam_from_world * wall_points_[i], &pixel) != ProjectionStatus::kValid) {
        continue;
      }
      if (noise_px > 0.0) pixel += Eigen::Vector2d(noise(random_), noise(random_));
      Eigen::Vector3d bearing;
      const bool has_bearing = camera_.Unproject(pixel, &bearing);
      features.keypoints.push_back(
          {cv::Point2f(static_cast<float>(pixel.x()), static_cast<float>(pixel.y())), 1.0f});
      features.bearings.push_back(bearing);
      features.has_bearing.push_back(has_bearing);
      seen->push_back(static_cast<int>(i));
    }
    return features;
  }

  // The correspondences of two frames: keypoints that see the same wall point.
  static PairMatches Matches(const std::vector<int>& key_seen, const std::vector<int>& seen) {
    PairMatches matches;
    std::vector<int> index_in_key(100000, -1);
    for (std::size_t k = 0; k < key_seen.size(); ++k)
      index_in_key[key_seen[k]] = static_cast<int>(k);
    for (std::size_t f = 0; f < seen.size(); ++f) {
      if (index_in_key[seen[f]] >= 0)
        matches.inliers.push_back({index_in_key[seen[f]], static_cast<int>(f)});
    }
    matches.matched = static_cast<int>(matches.inliers.size());
    return matches;
  }

  // Runs `frames` frames through the back end the way the sparse pipeline does (every
  // kFramesPerKeyFrame-th frame promoted) and returns the estimated trajectory.
  SparseOdometerOutput Run(int frames, double noise_px, SparseOdometerSummary* summary) {
    const SparseFeatures front_end(camera_, features_options_);
    SparseOdometer odometer(camera_, kRadius, start_, options_, front_end, nullptr);
    std::vector<SparseLocalisedFrame> localised;
    std::vector<int> key_seen, seen;
    odometer.StartAt(0, 0.0, Features(0, noise_px, &key_seen));
    localised.push_back({0, 0.0, 0, 0.0, {}});
    for (int k = 1; k < frames; ++k) {
      FrameFeatures features = Features(k, noise_px, &seen);
      const PairMatches matches = Matches(key_seen, seen);
      SparseLocalisedFrame frame{
          static_cast<std::size_t>(k), 0.1 * k, odometer.CurrentIndex(), 0.0, {}};
      frame.delta_h = odometer.AxialStep(features, matches, &frame.sightings);
      if (k % kFramesPerKeyFrame == 0) {
        odometer.Promote(k, 0.1 * k, std::move(features), matches, frame.delta_h);
        frame.anchor = odometer.CurrentIndex();
        frame.delta_h = 0.0;
        frame.sightings.clear();
        key_seen = seen;
      }
      localised.push_back(std::move(frame));
    }
    SparseOdometerOutput output = odometer.Finish(&localised);
    *summary = odometer.summary();
    return output;
  }

  Camera camera_;
  Eigen::Isometry3d start_;
  std::vector<Eigen::Vector3d> wall_points_;
  SparseFeatureOptions features_options_;
  SparseOdometerOptions options_;
  std::mt19937 random_{11};
};

TEST_F(SparseOdometerTest, ExactTracksGiveTheTravelAlongTheAxis) {
  constexpr int kFrames = 120;  // 20 key frames, 95 mm
  SparseOdometerSummary summary;
  const SparseOdometerOutput output = Run(kFrames, 0.0, &summary);
  ASSERT_EQ(output.trajectory.size(), static_cast<std::size_t>(kFrames));
  EXPECT_EQ(output.key_frames.size(), static_cast<std::size_t>(kFrames / kFramesPerKeyFrame));
  EXPECT_EQ(summary.key_frame_records.size(), output.key_frames.size());
  EXPECT_GE(summary.window_adjustments, 1);
  for (int k = 0; k < kFrames; ++k) {
    EXPECT_NEAR((output.trajectory[k].position - TruePose(k).translation()).norm(), 0.0, 2e-5)
        << "frame " << k;
  }
  // Every point seen in two key frames lies on the wall.
  ASSERT_GT(output.points.size(), 500u);
  for (const Eigen::Vector3d& point : output.points) {
    EXPECT_NEAR(point.head<2>().norm(), kRadius, 1e-9);
  }
}

TEST_F(SparseOdometerTest, NoisyTracksKeepTheScale) {
  constexpr int kFrames = 120;
  SparseOdometerSummary summary;
  const SparseOdometerOutput output = Run(kFrames, 0.3, &summary);
  const double travelled =
      output.trajectory.back().position.z() - output.trajectory[0].position.z();
  const double truth = kStep * (kFrames - 1);
  // 0.3 px of noise on 95 mm: well under 0.5 % of the travel.
  EXPECT_NEAR(travelled, truth, 0.005 * truth);
  for (int k = 0; k < kFrames; ++k) {
    EXPECT_NEAR(output.trajectory[k].position.z(), TruePose(k).translation().z(), 0.0005) << k;
  }
}

}  // namespace
}  // namespace pipescope
