#include "pipescope/feature/far_wall_corners.h"

namespace pipescope {

std::vector<cv::Point2f> FarWallCorners(const cv::Mat& grey, const cv::Mat& cone_mask,
                                        const RegionHarrisOptions& harris, int count,
                                        double duplicate_radius_px,
                                        const std::vector<cv::Point2f>& existing) {
  std::vector<cv::Point2f> corners;
  if (count <= 0) return corners;
  RegionHarrisOptions cone = harris;
  cone.grid_rows = cone.grid_cols = 1;
  cone.per_cell = count;
  const double radius_squared = duplicate_radius_px * duplicate_radius_px;
  for (const Keypoint& keypoint : DetectRegionHarris(grey, cone, cone_mask)) {
    bool duplicate = false;
    for (const cv::Point2f& point : existing) {
      const cv::Point2f offset = point - keypoint.position;
      if (offset.dot(offset) < radius_squared) {
        duplicate = true;
        break;
      }
    }
    if (!duplicate) corners.push_back(keypoint.position);
  }
  return corners;
}

}  // namespace pipescope
