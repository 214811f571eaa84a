#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "pipescope/image/gain_mask.h"
#include "pipescope/image/wall_unrolling.h"
#include "pipescope/synthetic/presets.h"
#include "pipescope/synthetic/simulation.h"

namespace pipescope {

// Zero-mean normalised cross-correlation of a and b (CV_32F) over the cells where `mask` is
// non-zero; 0 when either is constant there.
inline double MaskedZncc(const cv::Mat& a, const cv::Mat& b, const cv::Mat& mask) {
  cv::Scalar mean_a, std_a, mean_b, std_b;
  cv::meanStdDev(a, mean_a, std_a, mask);
  cv::meanStdDev(b, mean_b, std_b, mask);
  if (std_a[0] <= 0 || std_b[0] <= 0) return 0.0;
  cv::Mat product = (a - mean_a[0]).mul(b - mean_b[0]);
  return cv::mean(product, mask)[0] / (std_a[0] * std_b[0]);
}

// ZNCC of the fine texture only: a and b minus their local means (a normalised Gaussian blur
// over `mask`), so the slow lighting residue that gain correction leaves, which is alike at any
// small misalignment, does not hide a misregistration. Cells within 2 sigma of the mask's edge
// are left out.
inline double MaskedHighPassZncc(const cv::Mat& a, const cv::Mat& b, const cv::Mat& mask,
                                 double sigma = 2.0) {
  const auto high_pass = [&](const cv::Mat& image) {
    cv::Mat weight, masked, blurred_weight, blurred;
    mask.convertTo(weight, CV_32F, 1.0 / 255.0);
    image.copyTo(masked);
    masked.setTo(0.0f, mask == 0);
    cv::GaussianBlur(masked, blurred, cv::Size(), sigma);
    cv::GaussianBlur(weight, blurred_weight, cv::Size(), sigma);
    cv::Mat result = masked - blurred / cv::max(blurred_weight, 1e-6);
    return result;
  };
  cv::Mat inner;
  cv::erode(mask, inner, cv::Mat(), cv::Point(-1, -1), static_cast<int>(std::ceil(2 * sigma)));
  return MaskedZncc(high_pass(a), high_pass(b), inner);
}

// The simulator's albedo at each cell's (h, s) of `grid`, filtered to the cell size like a pixel:
// the ground truth an unrolled frame or mosaic must register with.
inline cv::Mat SimulatedWallAlbedo(const Simulation& simulation, const UnrolledGrid& grid) {
  const WallTexture& texture = simulation.texture();
  const double circumference = 2 * M_PI * grid.radius_m;
  cv::Mat albedo(grid.size, CV_32F);
  for (int v = 0; v < grid.size.height; ++v) {
    for (int u = 0; u < grid.size.width; ++u) {
      albedo.at<float>(v, u) =
          texture.Albedo(0, grid.h0_m + u * grid.pixel_m, grid.s0_m + v * grid.pixel_m,
                         circumference, grid.pixel_m);
    }
  }
  return albedo;
}

// The wall-looking 16-inch steel pipe of 000 (pipe 2) at a small image size, so tests render
// in milliseconds.
inline SimulationConfig SmallSteelConfig(int width = 320, int height = 240, int frames = 60) {
  SimulationConfig config = PresetConfig("steel-16in");
  config.width = width;
  config.height = height;
  config.frames = frames;
  config.white_card_count = 1;
  return config;
}

// Gain-corrected radiance of frame `index` (000 §3.2), with the mask from a white card.
class GainCorrectedFrames {
 public:
  explicit GainCorrectedFrames(const Simulation& simulation)
      : simulation_(simulation),
        mask_(BuildGainMask({simulation.RenderWhiteCardRadiance(0)}, 2.0)) {}
  cv::Mat Frame(int index) const {
    return ApplyGainMask(simulation_.RenderFrameRadiance(index), mask_);
  }

 private:
  const Simulation& simulation_;
  cv::Mat mask_;
};

}  // namespace pipescope
