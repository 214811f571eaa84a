#include "pipescope/pipeline/dense_frame_preparation.h"

#include <opencv2/imgproc.hpp>
#include <string>

#include "pipescope/image/gain_mask.h"
#include "pipescope/util/error.h"

namespace pipescope {

DenseFramePreparation::DenseFramePreparation(const Camera& camera, const cv::Mat& gain_mask,
                                             const DenseFrameOptions& options)
    : undistorter_(camera), gain_mask_(gain_mask), options_(options) {
  if (options.downsample < 1 || options.downsample > 16) {
    throw InputError("downsample: must be an integer in 1..16, got " +
                     std::to_string(options.downsample));
  }
  if (!gain_mask.empty() &&
      (gain_mask.cols != camera.Width() || gain_mask.rows != camera.Height())) {
    throw InputError("gain_mask: the mask is " + std::to_string(gain_mask.cols) + "x" +
                     std::to_string(gain_mask.rows) + " but the camera is " +
                     std::to_string(camera.Width()) + "x" + std::to_string(camera.Height()));
  }
}

cv::Size DenseFramePreparation::PreparedSize() const {
  const Camera& camera = undistorter_.rectified_camera();
  return {camera.Width() / options_.downsample, camera.Height() / options_.downsample};
}

cv::Point2d DenseFramePreparation::PreparedPrincipalPoint() const {
  const cv::Point2d full = PrincipalPoint(undistorter_.rectified_camera());
  const double factor = options_.downsample;
  return {(full.x + 0.5) / factor - 0.5, (full.y + 0.5) / factor - 0.5};
}

cv::Mat DownsampleByBlockMean(const cv::Mat& image, int factor) {
  if (factor == 1) return image;
  // INTER_AREA with an integer factor is the mean of each factor x factor block.
  const cv::Size size(image.cols / factor, image.rows / factor);
  cv::Mat downsampled;
  cv::resize(image(cv::Rect(0, 0, size.width * factor, size.height * factor)), downsampled, size, 0,
             0, cv::INTER_AREA);
  return downsampled;
}

cv::Mat DenseFramePreparation::Prepare(const cv::Mat& grey) const {
  const cv::Mat corrected = gain_mask_.empty() ? grey : ApplyGainMask(grey, gain_mask_);
  return DownsampleByBlockMean(undistorter_.Apply(corrected), options_.downsample);
}

}  // namespace pipescope
