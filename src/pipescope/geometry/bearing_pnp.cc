#include "pipescope/geometry/bearing_pnp.h"

#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <string>

#include "pipescope/util/error.h"

namespace pipescope {
namespace {

double AngleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / M_PI;
}

}  // namespace

BearingPnp SolveBearingPnp(const std::vector<Eigen::Vector3d>& points,
                           const std::vector<Eigen::Vector3d>& bearings,
                           const BearingPnpOptions& options) {
  if (points.size() != bearings.size()) {
    throw InputError("SolveBearingPnp: " + std::to_string(points.size()) + " points and " +
                     std::to_string(bearings.size()) + " bearings");
  }
  BearingPnp result;
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> image;
  std::vector<int> index;
  for (int i = 0; i < static_cast<int>(points.size()); ++i) {
    const Eigen::Vector3d b = bearings[i].normalized();
    if (b.z() < options.min_bearing_z) continue;
    object.emplace_back(points[i].x(), points[i].y(), points[i].z());
    image.emplace_back(b.x() / b.z(), b.y() / b.z());
    index.push_back(i);
  }
  if (object.size() < 6) return result;
  // On the normalised plane an angle of max_angle_deg is at least its tangent long (at the
  // axis); farther out it is longer, so RANSAC's threshold keeps a few more and the angle test
  // below decides.
  const double threshold = std::tan(options.max_angle_deg * M_PI / 180.0);
  const cv::Mat identity = cv::Mat::eye(3, 3, CV_64F);
  cv::Mat rvec, tvec;
  std::vector<int> ransac_inliers;
  if (!cv::solvePnPRansac(object, image, identity, cv::noArray(), rvec, tvec, false,
                          options.iterations, static_cast<float>(2.0 * threshold), 0.999,
                          ransac_inliers, cv::SOLVEPNP_EPNP) ||
      ransac_inliers.size() < 6) {
    return result;
  }
  std::vector<cv::Point3d> inlier_object;
  std::vector<cv::Point2d> inlier_image;
  for (int i : ransac_inliers) {
    inlier_object.push_back(object[i]);
    inlier_image.push_back(image[i]);
  }
  cv::solvePnPRefineLM(inlier_object, inlier_image, identity, cv::noArray(), rvec, tvec);
  cv::Mat rotation;
  cv::Rodrigues(rvec, rotation);
  Eigen::Matrix3d r;
  Eigen::Vector3d t;
  cv::cv2eigen(rotation, r);
  cv::cv2eigen(tvec, t);
  result.cam_from_points.linear() = r;
  result.cam_from_points.translation() = t;
  double sum = 0.0;
  for (std::size_t j = 0; j < index.size(); ++j) {
    const int i = index[j];
    const double angle = AngleDeg(result.cam_from_points * points[i], bearings[i]);
    if (angle > options.max_angle_deg) continue;
    result.inliers.push_back(i);
    sum += angle * angle;
  }
  if (result.inliers.size() < 6) return result;
  result.rms_deg = std::sqrt(sum / result.inliers.size());
  result.found = true;
  return result;
}

}  // namespace pipescope
