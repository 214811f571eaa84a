#include "pipescope/geometry/five_point_ransac.h"

#include <opencv2/calib3d.hpp>
#include <stdexcept>

namespace pipescope {

int FivePointRansacInliers(const std::vector<Eigen::Vector3d>& first,
                           const std::vector<Eigen::Vector3d>& second,
                           const FivePointRansacOptions& options, std::vector<bool>* inlier) {
  if (first.size() != second.size()) {
    throw std::invalid_argument("FivePointRansacInliers: bearing lists differ in length");
  }
  inlier->assign(first.size(), false);
  std::vector<cv::Point2d> points1, points2;
  std::vector<std::size_t> index;
  for (std::size_t i = 0; i < first.size(); ++i) {
    if (!(first[i].z() > 0.0) || !(second[i].z() > 0.0)) continue;
    points1.emplace_back(first[i].x() / first[i].z(), first[i].y() / first[i].z());
    points2.emplace_back(second[i].x() / second[i].z(), second[i].y() / second[i].z());
    index.push_back(i);
  }
  if (static_cast<int>(points1.size()) < std::max(5, options.min_correspondences)) return 0;
  cv::Mat mask;
  const cv::Mat essential = cv::findEssentialMat(
      points1, points2, cv::Mat::eye(3, 3, CV_64F), cv::RANSAC, options.confidence,
      options.threshold_px / options.focal_length_px, mask);
  if (essential.empty() || mask.empty()) return 0;
  int count = 0;
  for (std::size_t k = 0; k < index.size(); ++k) {
    if (mask.at<unsigned char>(static_cast<int>(k)) != 0) {
      (*inlier)[index[k]] = true;
      ++count;
    }
  }
  return count;
}

}  // namespace pipescope
