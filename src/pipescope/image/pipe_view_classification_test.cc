#include "pipescope/image/pipe_view_classification.h"

#include <gtest/gtest.h>

#include <limits>
#include <opencv2/imgproc.hpp>
#include <random>

#include "pipescope/synthetic/presets.h"
#include "pipescope/synthetic/sensor.h"
#include "pipescope/synthetic/simulation.h"

namespace pipescope {
namespace {

// Frames of the fiberglass-network preset (001's 190-degree lens in the 400 mm loop), rendered at
// 320x240 to stay fast, labelled by the camera's distance from the nearest T centre: T when
// within kTDistance, straight beyond kStraightDistance; the frames in between, where the T's side
// opening enters and leaves the 190-degree view (about 0.2 m from the centre with this 0.2 m
// turning radius), are not scored.
constexpr double kTDistance = 0.15;
constexpr double kStraightDistance = 0.5;

struct LabelledFrame {
  PipeViewClass truth;
  bool scored;
  double distance_m;
  PipeViewMeasurement measurement;
};

std::vector<LabelledFrame> ClassifyNetworkFrames(int first, int count, int step) {
  SimulationConfig config = PresetConfig("fiberglass-network");
  config.width = 320;
  config.height = 240;
  config.speed_m_s = 0.15;
  config.frames = first + count * step;
  const Simulation simulation(config);
  const PipeViewClassifier classifier(simulation.camera());
  // Exposure as the dataset writer sets it: the first white card's brightest pixel at the
  // exposure target.
  const cv::Mat vignetting = VignettingMap(simulation.camera(), config.vignetting);
  SensorOptions sensor;
  double max_value = 0.0;
  cv::minMaxLoc(simulation.RenderWhiteCardRadiance(0).mul(vignetting), nullptr, &max_value);
  sensor.exposure = config.exposure_target / max_value;
  std::vector<LabelledFrame> frames;
  for (int k = 0; k < count; ++k) {
    const int index = first + k * step;
    const Eigen::Vector3d position = simulation.FramePose(index).translation();
    double distance = std::numeric_limits<double>::infinity();
    for (const Scene::Junction& junction : simulation.layout().scene.junctions()) {
      distance = std::min(distance, (junction.center - position).norm());
    }
    LabelledFrame frame;
    frame.truth = distance < kTDistance ? PipeViewClass::kTIntersection : PipeViewClass::kStraight;
    frame.distance_m = distance;
    frame.scored = distance < kTDistance || distance > kStraightDistance;
    cv::Mat grey;
    ApplySensor(simulation.RenderFrameRadiance(index), vignetting, sensor, index)
        .convertTo(grey, CV_32F);
    frame.measurement = classifier.Classify(grey);
    frames.push_back(frame);
  }
  return frames;
}

TEST(PipeViewClassificationTest, SimulatedStraightAndTFramesAfterFiltering) {
  const std::vector<LabelledFrame> frames = ClassifyNetworkFrames(0, 200, 3);
  std::vector<PipeViewClass> initial;
  for (const LabelledFrame& frame : frames) initial.push_back(frame.measurement.view_class);
  const std::vector<PipeViewClass> filtered = FilterPipeViewClasses(initial, 3);
  int scored = 0, correct = 0, scored_t = 0, scored_straight = 0;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    if (!frames[k].scored) continue;
    ++scored;
    (frames[k].truth == PipeViewClass::kStraight ? scored_straight : scored_t)++;
    correct += filtered[k] == frames[k].truth ? 1 : 0;
  }
  ASSERT_GE(scored_t, 6);
  ASSERT_GT(scored_straight, 50);
  EXPECT_GE(correct, 0.95 * scored);
}

TEST(PipeViewClassificationTest, FilteringEnforcesMinimumClusterSize) {
  using C = PipeViewClass;
  const C S = C::kStraight, T = C::kTIntersection;
  const std::vector<C> classes = {S, S, S, S, T, S, S, S, S, T, T, T,
                                  T, T, S, T, T, T, T, S, S, S, S, S};
  const std::vector<C> expected = {S, S, S, S, S, S, S, S, S, T, T, T,
                                   T, T, T, T, T, T, T, S, S, S, S, S};
  EXPECT_EQ(FilterPipeViewClasses(classes, 3), expected);
  // Long enough runs are left alone.
  EXPECT_EQ(FilterPipeViewClasses(expected, 5), expected);
  // A single short run in a sequence of one class vanishes.
  EXPECT_EQ(FilterPipeViewClasses({S, S, S, T, S, S, S}, 2), std::vector<C>(7, S));
}

TEST(PipeViewClassificationTest, SettledCountEndsAtTheLastLongRun) {
  using C = PipeViewClass;
  const C S = C::kStraight, T = C::kTIntersection;
  EXPECT_EQ(SettledPipeViewClassCount({S, S, T, S, S}, 3), 0);
  EXPECT_EQ(SettledPipeViewClassCount({S, S, S, T, S}, 3), 3);
  EXPECT_EQ(SettledPipeViewClassCount({S, S, S, T, T, T, T, S, S}, 3), 7);
  EXPECT_EQ(SettledPipeViewClassCount({T, S, S, S}, 3), 4);
  EXPECT_EQ(SettledPipeViewClassCount({T, S}, 1), 2);
}

// The settled classes of every prefix equal the whole sequence's filtered classes, on random
// sequences from steady (long runs, rare flickers) to noisy ones.
TEST(PipeViewClassificationTest, SettledPrefixFiltersAsTheWholeSequence) {
  using C = PipeViewClass;
  std::mt19937 generator(7);
  int settled_total = 0;
  for (const double flip_probability : {0.02, 0.1, 0.3, 0.5}) {
    for (const int min_cluster_size : {1, 3, 10}) {
      for (int trial = 0; trial < 20; ++trial) {
        std::bernoulli_distribution flip(flip_probability);
        std::vector<C> classes;
        C current = C::kStraight;
        for (int k = 0; k < 300; ++k) {
          if (flip(generator)) {
            current = current == C::kStraight ? C::kTIntersection : C::kStraight;
          }
          classes.push_back(current);
        }
        const std::vector<C> whole = FilterPipeViewClasses(classes, min_cluster_size);
        for (std::size_t length = 1; length <= classes.size(); ++length) {
          const std::vector<C> prefix(classes.begin(), classes.begin() + length);
          const int settled = SettledPipeViewClassCount(prefix, min_cluster_size);
          ASSERT_LE(settled, static_cast<int>(length));
          const std::vector<C> filtered = FilterPipeViewClasses(prefix, min_cluster_size);
          for (int k = 0; k < settled; ++k) {
            ASSERT_EQ(filtered[k], whole[k])
                << "flip " << flip_probability << " min " << min_cluster_size << " trial " << trial
                << " prefix " << length << " key frame " << k;
          }
          settled_total += settled;
        }
      }
    }
  }
  EXPECT_GT(settled_total, 0);
}

TEST(PipeViewClassificationTest, RoundCentralBlobIsStraightOffCentreIsT) {
  const Camera camera(CameraModelId::kFisheyePoly, 320, 240, {73.0, -0.7, 0.0, 0.0, 159.5, 119.5});
  const PipeViewClassifier classifier(camera);
  cv::Mat centred(240, 320, CV_32F, cv::Scalar(150.f));
  cv::circle(centred, cv::Point(160, 120), 30, cv::Scalar(10.f), cv::FILLED);
  const PipeViewMeasurement straight = classifier.Classify(centred);
  EXPECT_EQ(straight.view_class, PipeViewClass::kStraight);
  // A disc centred on the principal point: L_p / L = 1.
  EXPECT_NEAR(straight.moment_ratio, 1.0, 0.05);
  cv::Mat off(240, 320, CV_32F, cv::Scalar(150.f));
  cv::circle(off, cv::Point(220, 120), 25, cv::Scalar(10.f), cv::FILLED);
  const PipeViewMeasurement t = classifier.Classify(off);
  EXPECT_EQ(t.view_class, PipeViewClass::kTIntersection);
  // A disc of radius R offset by d: L_p / L = 1 + 2 d^2 / R^2 (at half resolution R ~ 12, d = 30).
  EXPECT_NEAR(t.moment_ratio, 1.0 + 2.0 * 30.0 * 30.0 / (11.5 * 11.5), 3.0);
}

}  // namespace
}  // namespace pipescope
