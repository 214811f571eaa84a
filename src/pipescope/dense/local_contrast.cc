#include "pipescope/dense/local_contrast.h"

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <string>

#include "pipescope/util/error.h"

namespace pipescope {

cv::Mat NormaliseLocalContrast(const cv::Mat& image, double sigma_px, double floor_fraction) {
  if (image.empty() || image.channels() != 1) {
    throw InputError("local contrast normalisation: needs a non-empty one-channel image");
  }
  if (!(sigma_px > 0.0) || !std::isfinite(sigma_px)) {
    throw InputError("local contrast normalisation: sigma must be positive, got " +
                     std::to_string(sigma_px));
  }
  cv::Mat value;
  image.convertTo(value, CV_32F);
  // Local means over the image only (normalised convolution): a mirrored border would add a
  // pattern fixed in the frame near its edges, the very thing this removes.
  cv::Mat coverage;
  cv::GaussianBlur(cv::Mat::ones(value.size(), CV_32F), coverage, cv::Size(), sigma_px, 0.0,
                   cv::BORDER_CONSTANT);
  const auto local_mean = [&](const cv::Mat& field) {
    cv::Mat blurred;
    cv::GaussianBlur(field, blurred, cv::Size(), sigma_px, 0.0, cv::BORDER_CONSTANT);
    return cv::Mat(blurred / coverage);
  };
  const cv::Mat detail = value - local_mean(value);
  const cv::Mat variance = local_mean(detail.mul(detail));
  const double variance_floor = floor_fraction * cv::mean(variance)[0] + 1e-12;
  cv::Mat contrast;
  cv::sqrt(variance + variance_floor, contrast);
  return detail / contrast;
}

}  // namespace pipescope
