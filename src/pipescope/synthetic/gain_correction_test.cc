// Issue 4's target for gain-mask correction (000 §3.2): on a uniform-albedo wall, the slow
// intensity variation across a corrected frame is at least 90 % smaller than before. Checked on
// the two set-ups of 000 with the presets' default specular sheen (000 §6.2.1). The white cards
// have the wall's own finish, so the mask holds the highlight as seen from the nominal pose; a
// matte card's mask cannot, and leaves most of the sheen in the corrected frame.
//
// The robot's pitch and yaw wobble moves the highlight away from where the mask has it (the
// lateral offset and roll barely matter: measured, zeroing them changes nothing), so the target
// is checked per frame without the wobble, and on average with it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <tuple>

#include "pipescope/image/gain_mask.h"
#include "pipescope/io/image_source.h"
#include "pipescope/synthetic/dataset_writer.h"
#include "pipescope/synthetic/presets.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

constexpr int kFrames = 12;

// Relative spread (std / mean) of the low-passed image inside a margin: the lighting pattern,
// without the pixel noise.
double LowFrequencyVariation(const cv::Mat& image) {
  const double sigma = 0.05 * image.cols;
  cv::Mat low;
  cv::GaussianBlur(image, low, cv::Size(), sigma, sigma, cv::BORDER_REFLECT);
  const int margin = static_cast<int>(3 * sigma);
  const cv::Mat inner = low(cv::Rect(margin, margin, low.cols - 2 * margin, low.rows - 2 * margin));
  cv::Scalar mean, stddev;
  cv::meanStdDev(inner, mean, stddev);
  return stddev[0] / mean[0];
}

struct Reduction {
  double before = 0;  // low-frequency variation of the frame
  double after = 0;   // and of the corrected frame
  double Percent() const { return 100.0 * (1.0 - after / before); }
};

double MeanPercent(const std::vector<Reduction>& reductions) {
  double sum = 0;
  for (const Reduction& r : reductions) sum += r.Percent();
  return sum / static_cast<double>(reductions.size());
}

// Simulates `preset` on a uniform wall with its default sheen and the given white-card finish,
// and measures the reduction on each frame. The robot drives 100 times faster than the preset,
// so the frames spread over metres of the run and sample the wobble (offsets and angles are
// functions of the distance driven). Each dataset is simulated once per test program.
const std::vector<Reduction>& Reductions(const std::string& preset, const std::string& finish,
                                         bool wobble) {
  static std::map<std::tuple<std::string, std::string, bool>, std::vector<Reduction>> cache;
  const auto key = std::make_tuple(preset, finish, wobble);
  if (const auto it = cache.find(key); it != cache.end()) return it->second;
  SimulationConfig config = PresetConfig(preset);
  config.texture_contrast = 0.0;
  config.white_card_finish = finish;
  config.width = 320;
  config.height = 240;
  config.frames = kFrames;
  config.speed_m_s *= 100.0;
  if (!wobble) config.wobble_deg = 0.0;
  const std::string name = preset + "_" + finish + (wobble ? "_wobble" : "");
  const auto dir = MakeTestDirectory("gain_correction_" + name);
  SimulateDataset(config, dir / "ds");
  const cv::Mat mask = ReadGainMask(dir / "ds" / "gain_mask.png");
  std::vector<Reduction> reductions;
  for (int i = 0; i < kFrames; ++i) {
    char file[32];
    std::snprintf(file, sizeof(file), "%06d.png", i);
    const cv::Mat frame =
        ToFloatGrey(cv::imread((dir / "ds" / "images" / file).string(), cv::IMREAD_UNCHANGED));
    const Reduction r{LowFrequencyVariation(frame),
                      LowFrequencyVariation(ApplyGainMask(frame, mask))};
    std::printf("%s frame %d: low-frequency variation %.4f -> %.4f (%.1f %% less)\n", name.c_str(),
                i, r.before, r.after, r.Percent());
    reductions.push_back(r);
  }
  return cache[key] = reductions;
}

std::string TestName(const ::testing::TestParamInfo<std::string>& info) {
  std::string name = info.param;
  std::replace(name.begin(), name.end(), '-', '_');
  return name;
}

class GainCorrectionTest : public ::testing::TestWithParam<std::string> {};

TEST_P(GainCorrectionTest, WallFinishCardsFlattenAShinyUniformWallByNinetyPercent) {
  // Measured 98.3-99.6 % a frame.
  for (const Reduction& r : Reductions(GetParam(), "wall", false)) {
    EXPECT_GT(r.before, 0.02);  // there is a lighting pattern to remove
    EXPECT_LT(r.after, 0.1 * r.before);
  }
}

TEST_P(GainCorrectionTest, WallFinishCardsFlattenAWobblingRobotsFramesByNinetyPercentOnAverage) {
  // Measured: steel-6in 95.0-98.9 % (mean 97.6), steel-16in 87.6-97.8 % (mean 93.8); the
  // 16-inch camera's 25 degree view makes the moving highlight a larger part of the frame.
  const std::vector<Reduction>& reductions = Reductions(GetParam(), "wall", true);
  for (const Reduction& r : reductions) EXPECT_GT(r.Percent(), 85.0);
  EXPECT_GT(MeanPercent(reductions), 90.0);
}

TEST_P(GainCorrectionTest, MatteCardsLeaveTheSheen) {
  // Measured 42 % (steel-16in) and 49 % (steel-6in) a frame, residuals 29 to 144 times the
  // wall-finish mask's.
  const std::vector<Reduction>& wall = Reductions(GetParam(), "wall", false);
  const std::vector<Reduction>& matte = Reductions(GetParam(), "matte", false);
  for (int i = 0; i < kFrames; ++i) {
    EXPECT_LT(matte[i].Percent(), 60.0) << "frame " << i;
    EXPECT_GT(matte[i].after, 5.0 * wall[i].after) << "frame " << i;
  }
}

INSTANTIATE_TEST_SUITE_P(WallLookingPresets, GainCorrectionTest,
                         ::testing::Values("steel-6in", "steel-16in"), TestName);

}  // namespace
}  // namespace pipescope
