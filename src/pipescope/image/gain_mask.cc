#include "pipescope/image/gain_mask.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "pipescope/io/image_source.h"
#include "pipescope/util/atomic_file.h"
#include "pipescope/util/error.h"

namespace pipescope {
namespace {

// Mask values below 1 % of its maximum are clamped, so a lens's dark rim does not explode.
constexpr double kMinGain = 0.01;

cv::Mat NormaliseToUnitMaximum(const cv::Mat& image, const std::string& what) {
  double max_value = 0.0;
  cv::minMaxLoc(image, nullptr, &max_value);
  if (!(max_value > 0.0)) throw InputError(what + " is black: no gain mask can be made from it");
  return image / max_value;
}

}  // namespace

cv::Mat BuildGainMask(const std::vector<cv::Mat>& white_card_images, double sigma_px) {
  if (white_card_images.empty()) throw InputError("no white-card images for the gain mask");
  cv::Mat sum = cv::Mat::zeros(white_card_images.front().size(), CV_32F);
  for (const cv::Mat& image : white_card_images) {
    if (image.size() != sum.size()) {
      throw InputError("white-card images differ in size: " + std::to_string(image.cols) + "x" +
                       std::to_string(image.rows) + " and " + std::to_string(sum.cols) + "x" +
                       std::to_string(sum.rows));
    }
    sum += ToFloatGrey(image);
  }
  cv::Mat mean = sum / static_cast<double>(white_card_images.size());
  if (sigma_px > 0)
    cv::GaussianBlur(mean, mean, cv::Size(), sigma_px, sigma_px, cv::BORDER_REFLECT);
  return NormaliseToUnitMaximum(mean, "the mean white-card image");
}

cv::Mat GainCorrectionFactors(const cv::Mat& mask) {
  cv::Mat gain;
  cv::max(mask, kMinGain, gain);
  cv::Mat factors;
  cv::divide(1.0, gain, factors, CV_32F);
  return factors;
}

cv::Mat ApplyGainMask(const cv::Mat& image, const cv::Mat& mask) {
  if (image.size() != mask.size()) {
    throw InputError("the gain mask is " + std::to_string(mask.cols) + "x" +
                     std::to_string(mask.rows) + " but the frame is " + std::to_string(image.cols) +
                     "x" + std::to_string(image.rows));
  }
  const cv::Mat factors = GainCorrectionFactors(mask);
  cv::Mat image_float;
  image.convertTo(image_float, CV_MAKETYPE(CV_32F, image.channels()));
  if (image.channels() == 1) return image_float.mul(factors);
  std::vector<cv::Mat> channels;
  cv::split(image_float, channels);
  for (cv::Mat& channel : channels) channel = channel.mul(factors);
  cv::Mat corrected;
  cv::merge(channels, corrected);
  return corrected;
}

void WriteGainMask(const std::filesystem::path& path, const cv::Mat& mask) {
  cv::Mat mask16;
  NormaliseToUnitMaximum(mask, "the gain mask").convertTo(mask16, CV_16U, 65535.0);
  WriteFileAtomically(path, [&](const std::filesystem::path& temporary) {
    if (!cv::imwrite(temporary.string(), mask16)) {
      throw InputError("cannot write gain mask " + path.string());
    }
  });
}

cv::Mat ReadGainMask(const std::filesystem::path& path) {
  const cv::Mat image = cv::imread(path.string(), cv::IMREAD_ANYDEPTH | cv::IMREAD_GRAYSCALE);
  if (image.empty()) throw InputError("cannot read gain mask " + path.string());
  return NormaliseToUnitMaximum(ToFloatGrey(image), "gain mask " + path.string());
}

cv::Mat ReadDatasetGainMask(const std::filesystem::path& path, int width, int height) {
  if (path.empty()) return cv::Mat();
  cv::Mat mask = ReadGainMask(path);
  if (mask.cols != width || mask.rows != height) {
    throw InputError(path.string() + ": gain mask size differs from the camera's");
  }
  return mask;
}

}  // namespace pipescope
