#include "pipescope/image/undistortion.h"

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

Undistorter::Undistorter(const Camera& camera, const LineStretch& stretch)
    : rectified_(MakeRectifiedCamera(camera)) {
  const double f = CentralFocalLengthPx(camera);
  const cv::Point2d c = PrincipalPoint(camera);
  const std::vector<double>& factors = stretch.factors;
  if (!factors.empty() &&
      static_cast<int>(factors.size()) != (stretch.along_x ? camera.Height() : camera.Width())) {
    throw InputError("line stretch: " + std::to_string(factors.size()) +
                     " factors for a camera of " + std::to_string(camera.Width()) + "x" +
                     std::to_string(camera.Height()));
  }
  map_x_.create(camera.Height(), camera.Width(), CV_32F);
  map_y_.create(camera.Height(), camera.Width(), CV_32F);
  for (int y = 0; y < camera.Height(); ++y) {
    for (int x = 0; x < camera.Width(); ++x) {
      double sx = x, sy = y;
      if (!factors.empty() && stretch.along_x) sx = c.x + factors[y] * (x - c.x);
      if (!factors.empty() && !stretch.along_x) sy = c.y + factors[x] * (y - c.y);
      const Eigen::Vector3d ray((sx - c.x) / f, (sy - c.y) / f, 1.0);
      Eigen::Vector2d source;
      const ProjectionStatus status = camera.Project(ray, &source);
      const bool seen = status == ProjectionStatus::kValid;
      // Out-of-view pixels point outside the source so cv::remap fills them with 0.
      map_x_.at<float>(y, x) = seen ? static_cast<float>(source.x()) : -10.0f;
      map_y_.at<float>(y, x) = seen ? static_cast<float>(source.y()) : -10.0f;
    }
  }
  cv::convertMaps(map_x_, map_y_, fixed_map_xy_, fixed_map_fraction_, CV_16SC2);
}

cv::Mat Undistorter::Apply(const cv::Mat& image) const {
  CV_Assert(image.cols == map_x_.cols && image.rows == map_x_.rows);
  cv::Mat rectified;
  cv::remap(image, rectified, fixed_map_xy_, fixed_map_fraction_, cv::INTER_LINEAR,
            cv::BORDER_CONSTANT, 0);
  return rectified;
}

}  // namespace pipescope
