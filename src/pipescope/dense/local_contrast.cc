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
  // pattern fixed in the frame near its edges, the very thing this removes. The kernel is
  // cv::GaussianBlur's for float images (4 sigma each side). With zeros outside, the weight
  // inside the image is separable, so it costs two 1D filters instead of a third 2D blur.
  const int size = cvRound(sigma_px * 4.0 * 2.0 + 1.0) | 1;
  const cv::Mat kernel = cv::getGaussianKernel(size, sigma_px, CV_32F);
  const auto blur = [&](const cv::Mat& field, const cv::Mat& kernel_x, const cv::Mat& kernel_y) {
    cv::Mat blurred;
    cv::sepFilter2D(field, blurred, CV_32F, kernel_x, kernel_y, cv::Point(-1, -1), 0.0,
                    cv::BORDER_CONSTANT);
    return blurred;
  };
  const cv::Mat one(1, 1, CV_32F, cv::Scalar(1.0f));
  const cv::Mat weight_x = blur(cv::Mat::ones(1, value.cols, CV_32F), kernel, one);
  const cv::Mat weight_y = blur(cv::Mat::ones(value.rows, 1, CV_32F), one, kernel);
  const cv::Mat coverage = weight_y * weight_x;  // outer product, rows x cols
  const auto local_mean = [&](const cv::Mat& field) {
    return cv::Mat(blur(field, kernel, kernel) / coverage);
  };
  const cv::Mat detail = value - local_mean(value);
  const cv::Mat variance = local_mean(detail.mul(detail));
  const double variance_floor = floor_fraction * cv::mean(variance)[0] + 1e-12;
  cv::Mat contrast;
  cv::sqrt(variance + variance_floor, contrast);
  return detail / contrast;
}

}  // namespace pipescope
