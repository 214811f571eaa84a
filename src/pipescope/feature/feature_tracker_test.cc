// The fisheye tracker on frames the simulator renders (001 §III-A): features stay inside the
// configured view angle, where the wall is far enough from the lens to be tracked.
#include "pipescope/feature/feature_tracker.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "pipescope/synthetic/presets.h"
#include "pipescope/synthetic/simulation.h"

namespace pipescope {
namespace {

// A straight stretch of the fisheye preset at 640x480.
SimulationConfig StraightFisheyeConfig(int frames) {
  SimulationConfig config = PresetConfig("fiberglass-network");
  config.layout = "straight";
  config.length_m = 2.0;
  config.width = 640;
  config.height = 480;
  config.frames = frames;
  return config;
}

// Frame `index` as the tracker takes it: the rendered radiance scaled to a peak of 200.
cv::Mat RenderedGrey(const Simulation& simulation, int index) {
  const cv::Mat radiance = simulation.RenderFrameRadiance(index);
  double peak = 0.0;
  cv::minMaxLoc(radiance, nullptr, &peak);
  cv::Mat grey;
  radiance.convertTo(grey, CV_32F, 200.0 / std::max(peak, 1e-12));
  return grey;
}

// The largest angle from the optical axis among the features of the first key frames.
double LargestFeatureAngleDeg(const Simulation& simulation, const FeatureTrackerOptions& options) {
  FeatureTracker tracker(simulation.camera(), options);
  double largest = 0.0;
  for (int index = 0; index < 3; ++index) {
    const cv::Mat grey = RenderedGrey(simulation, index);
    TrackedKeyframe keyframe;
    const TrackingStep step = tracker.Track(grey, index, &keyframe);
    if (!step.keyframe) continue;
    for (const TrackedFeature& feature : keyframe.features) {
      largest = std::max(largest, std::acos(std::clamp(feature.bearing.z(), -1.0, 1.0)));
    }
  }
  return largest * 180.0 / M_PI;
}

TEST(FisheyeTracking, FeaturesStayWithinTheViewAngle) {
  const Simulation simulation(StraightFisheyeConfig(3));

  const FeatureTrackerOptions defaults;
  EXPECT_EQ(defaults.max_view_angle_deg, 70.0);
  const double largest = LargestFeatureAngleDeg(simulation, defaults);
  EXPECT_LE(largest, defaults.max_view_angle_deg + 1e-9);
  // The limit binds, not the texture; the 31 x 31 descriptor region keeps corners about 6
  // degrees inside it at this size.
  EXPECT_GT(largest, defaults.max_view_angle_deg - 10.0);

  // The lens itself sees to 95 degrees, and corners are found out there without the limit.
  FeatureTrackerOptions whole_lens;
  whole_lens.max_view_angle_deg = 95.0;
  EXPECT_GT(LargestFeatureAngleDeg(simulation, whole_lens), defaults.max_view_angle_deg + 5.0);
}

// A key frame's descriptors reuse the rows computed for its detections and compute only the
// guided matches': they must equal descriptors computed afresh at every feature.
TEST(FisheyeTracking, KeyframeDescriptorsEqualFreshOnes) {
  SimulationConfig config = StraightFisheyeConfig(6);
  config.speed_m_s = 0.075;  // 1 cm a frame, as the benchmark
  const Simulation simulation(config);
  const FeatureTrackerOptions options;
  FeatureTracker tracker(simulation.camera(), options);
  int keyframes = 0, guided = 0;
  for (int index = 0; index < config.frames; ++index) {
    const cv::Mat grey = RenderedGrey(simulation, index);
    TrackedKeyframe keyframe;
    if (!tracker.Track(grey, index, &keyframe).keyframe) continue;
    ++keyframes;
    guided += keyframe.matches_guided;
    std::vector<cv::Point2f> pixels;
    for (const TrackedFeature& feature : keyframe.features) pixels.push_back(feature.pixel);
    const cv::Mat fresh = ComputeTemplateDescriptors(grey, pixels, options.descriptor);
    ASSERT_EQ(tracker.keyframe_descriptors().rows, fresh.rows);
    EXPECT_EQ(cv::norm(tracker.keyframe_descriptors(), fresh, cv::NORM_INF), 0.0) << index;
  }
  EXPECT_GE(keyframes, 2);
  EXPECT_GT(guided, 0);  // both kinds of rows were checked
}

}  // namespace
}  // namespace pipescope
