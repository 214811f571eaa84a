#include "pipescope/image/undistortion.h"

#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <string>

#include "pipescope/util/error.h"

namespace pipescope {
namespace {

Camera MakeRectifiedCamera(const Camera& camera) {
  const double f = CentralFocalLengthPx(camera);
  const cv::Point2d c = PrincipalPoint(camera);
  return Camera(CameraModelId::kPinholeRadtan, camera.Width(), camera.Height(),
                {f, f, c.x, c.y, 0.0, 0.0, 0.0, 0.0, 0.0});
}

}  // namespace

double CentralFocalLengthPx(const Camera& camera) {
  return camera.Params()[0];  // fx, or k1 for fisheye-poly
}

cv::Point2d PrincipalPoint(const Camera& camera) {
  const std::vector<double>& params = camera.Params();
  if (camera.ModelId() == CameraModelId::kFisheyePoly) return {params[4], params[5]};
  return {params[2], params[3]};
}

Undistorter::Undistorter(const Camera& camera, const UndistorterOptions& options)
    : rectified_(MakeRectifiedCamera(camera)), interpolation_(options.interpolation) {
  const LineStretch& stretch = options.stretch;
  const int downsample = options.downsample;
  const double f = CentralFocalLengthPx(camera);
  const cv::Point2d c = PrincipalPoint(camera);
  const std::vector<double>& factors = stretch.factors;
  if (!factors.empty() &&
      static_cast<int>(factors.size()) != (stretch.along_x ? camera.Height() : camera.Width())) {
    throw InputError("line stretch: " + std::to_string(factors.size()) +
                     " factors for a camera of " + std::to_string(camera.Width()) + "x" +
                     std::to_string(camera.Height()));
  }
  if (downsample < 1 || downsample > 16) {
    throw InputError("downsample: must be an integer in 1..16, got " + std::to_string(downsample));
  }
  // The stretch factor of a full-resolution line coordinate that may fall between lines.
  auto stretch_at = [&factors](double line) {
    const double clamped = std::clamp(line, 0.0, static_cast<double>(factors.size() - 1));
    const auto below = static_cast<std::size_t>(clamped);
    const std::size_t above = std::min(below + 1, factors.size() - 1);
    const double t = clamped - static_cast<double>(below);
    return (1.0 - t) * factors[below] + t * factors[above];
  };
  const double scale = downsample;
  auto to_full = [scale](int block) { return (block + 0.5) * scale - 0.5; };
  auto to_block = [scale](double full) { return (full + 0.5) / scale - 0.5; };
  const int width = camera.Width() / downsample, height = camera.Height() / downsample;
  map_x_.create(height, width, CV_32F);
  map_y_.create(height, width, CV_32F);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const double full_x = to_full(x), full_y = to_full(y);
      double sx = full_x, sy = full_y;
      if (!factors.empty() && stretch.along_x) sx = c.x + stretch_at(full_y) * (full_x - c.x);
      if (!factors.empty() && !stretch.along_x) sy = c.y + stretch_at(full_x) * (full_y - c.y);
      const Eigen::Vector3d ray((sx - c.x) / f, (sy - c.y) / f, 1.0);
      Eigen::Vector2d source;
      const ProjectionStatus status = camera.Project(ray, &source);
      const bool seen = status == ProjectionStatus::kValid;
      // Out-of-view pixels point outside the source so cv::remap fills them with 0.
      map_x_.at<float>(y, x) = seen ? static_cast<float>(to_block(source.x())) : -10.0f;
      map_y_.at<float>(y, x) = seen ? static_cast<float>(to_block(source.y())) : -10.0f;
    }
  }
  cv::convertMaps(map_x_, map_y_, fixed_map_xy_, fixed_map_fraction_, CV_16SC2);
}

cv::Mat Undistorter::Apply(const cv::Mat& image) const {
  CV_Assert(image.cols == map_x_.cols && image.rows == map_x_.rows);
  cv::Mat rectified;
  cv::remap(image, rectified, fixed_map_xy_, fixed_map_fraction_, interpolation_,
            cv::BORDER_CONSTANT, 0);
  return rectified;
}

}  // namespace pipescope
