#include "pipescope/image/dense_frame_preparation.h"

#include <string>
#include <vector>

#include "pipescope/image/gain_mask.h"
#include "pipescope/io/image_source.h"
#include "pipescope/util/error.h"

namespace pipescope {
namespace {

// Sums `factor` rows into a full-width row, then `factor` columns into each output pixel: the
// row loop is a plain multiply-add over contiguous memory that the compiler vectorises.
template <typename T>
void WeightedBlockMeanRows(const cv::Mat& image, const cv::Mat& weight, int factor, float scale,
                           cv::Mat* out) {
  const int width = out->cols * factor;
  const float normalisation = scale / static_cast<float>(factor * factor);
  std::vector<float> row_sum(width);
  for (int v = 0; v < out->rows; ++v) {
    std::fill(row_sum.begin(), row_sum.end(), 0.0f);
    for (int i = 0; i < factor; ++i) {
      const T* in = image.ptr<T>(v * factor + i);
      if (weight.empty()) {
        for (int x = 0; x < width; ++x) row_sum[x] += static_cast<float>(in[x]);
      } else {
        const float* w = weight.ptr<float>(v * factor + i);
        for (int x = 0; x < width; ++x) row_sum[x] += static_cast<float>(in[x]) * w[x];
      }
    }
    float* result = out->ptr<float>(v);
    for (int u = 0; u < out->cols; ++u) {
      float sum = 0.0f;
      for (int j = 0; j < factor; ++j) sum += row_sum[u * factor + j];
      result[u] = sum * normalisation;
    }
  }
}

}  // namespace

cv::Mat WeightedBlockMean(const cv::Mat& image, const cv::Mat& weight, int factor, float scale) {
  CV_Assert(image.channels() == 1 && factor >= 1);
  CV_Assert(weight.empty() || (weight.type() == CV_32F && weight.size() == image.size()));
  cv::Mat out(image.rows / factor, image.cols / factor, CV_32F);
  switch (image.depth()) {
    case CV_8U:
      WeightedBlockMeanRows<std::uint8_t>(image, weight, factor, scale, &out);
      break;
    case CV_16U:
      WeightedBlockMeanRows<std::uint16_t>(image, weight, factor, scale, &out);
      break;
    case CV_32F:
      WeightedBlockMeanRows<float>(image, weight, factor, scale, &out);
      break;
    default:
      throw InputError("frames must be 8- or 16-bit or float grey images");
  }
  return out;
}

cv::Mat DownsampleByBlockMean(const cv::Mat& image, int factor) {
  if (factor == 1) return image;
  return WeightedBlockMean(image, cv::Mat(), factor);
}

namespace {

void RequireFactor(int factor) {
  if (factor < 1 || factor > 16) {
    throw InputError("downsample: must be an integer in 1..16, got " + std::to_string(factor));
  }
}

}  // namespace

cv::Size PreparedFrameSize(const Camera& camera, int factor) {
  RequireFactor(factor);
  return {camera.Width() / factor, camera.Height() / factor};
}

cv::Point2d PreparedFramePrincipalPoint(const Camera& camera, int factor) {
  RequireFactor(factor);
  const cv::Point2d full = PrincipalPoint(camera);
  return {(full.x + 0.5) / factor - 0.5, (full.y + 0.5) / factor - 0.5};
}

DenseFramePreparation::DenseFramePreparation(const Camera& camera, const cv::Mat& gain_mask,
                                             const DenseFrameOptions& options,
                                             const LineStretch& stretch)
    : undistorter_(
          camera,
          {.stretch = stretch, .downsample = options.downsample, .interpolation = cv::INTER_CUBIC}),
      options_(options) {
  if (!gain_mask.empty() &&
      (gain_mask.cols != camera.Width() || gain_mask.rows != camera.Height())) {
    throw InputError("gain_mask: the mask is " + std::to_string(gain_mask.cols) + "x" +
                     std::to_string(gain_mask.rows) + " but the camera is " +
                     std::to_string(camera.Width()) + "x" + std::to_string(camera.Height()));
  }
  if (!gain_mask.empty()) correction_ = GainCorrectionFactors(gain_mask);
}

cv::Mat DenseFramePreparation::Prepare(const cv::Mat& grey) const {
  return undistorter_.Apply(CorrectAndDownsample(grey));
}

cv::Mat DenseFramePreparation::CorrectAndDownsample(const cv::Mat& grey) const {
  const auto scale = static_cast<float>(GreyLevelsPerUnit(grey.depth()));
  return WeightedBlockMean(grey, correction_, options_.downsample, scale);
}

}  // namespace pipescope
