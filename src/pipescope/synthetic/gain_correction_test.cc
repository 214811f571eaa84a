// Issue 4's target for gain-mask correction (000 §3.2): on a uniform-albedo wall, the slow
// intensity variation across a corrected frame is at least 90 % smaller than before. Checked on
// the two set-ups of 000, whose robots ride near the pipe axis as the white card was imaged.
// Highlights are off: they move with the viewpoint, and no mask of a matte card can remove them
// (000 §6.2.1); with the presets' default sheen the reduction is about 50 % on steel.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "pipescope/image/gain_mask.h"
#include "pipescope/io/image_source.h"
#include "pipescope/synthetic/dataset_writer.h"
#include "pipescope/synthetic/presets.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

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

class GainCorrectionTest : public ::testing::TestWithParam<std::string> {};

TEST_P(GainCorrectionTest, FlattensAUniformWallByNinetyPercent) {
  SimulationConfig config = PresetConfig(GetParam());
  config.texture_contrast = 0.0;
  config.specular_strength = 0.0;
  config.width = 320;
  config.height = 240;
  config.frames = 3;
  const auto dir = MakeTestDirectory("gain_correction_" + GetParam());
  SimulateDataset(config, dir / "ds");
  const cv::Mat mask = ReadGainMask(dir / "ds" / "gain_mask.png");
  for (int i = 0; i < 3; ++i) {
    const cv::Mat frame = ToFloatGrey(
        cv::imread((dir / "ds" / "images" / ("00000" + std::to_string(i) + ".png")).string(),
                   cv::IMREAD_UNCHANGED));
    const double before = LowFrequencyVariation(frame);
    const double after = LowFrequencyVariation(ApplyGainMask(frame, mask));
    std::printf("%s frame %d: low-frequency variation %.4f -> %.4f (%.1f %% less)\n",
                GetParam().c_str(), i, before, after, 100.0 * (1.0 - after / before));
    EXPECT_GT(before, 0.02);  // there is a lighting pattern to remove
    EXPECT_LT(after, 0.1 * before);
  }
}

INSTANTIATE_TEST_SUITE_P(WallLookingPresets, GainCorrectionTest,
                         ::testing::Values("steel-6in", "steel-16in"), [](const auto& info) {
                           std::string name = info.param;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

}  // namespace
}  // namespace pipescope
