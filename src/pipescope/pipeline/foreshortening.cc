#include "pipescope/pipeline/foreshortening.h"

#include <optional>

#include "pipescope/mapping/wall_unrolling.h"

namespace pipescope {

ForeshorteningProfile::ForeshorteningProfile(const Eigen::Isometry3d& start_world_from_cam,
                                             double radius_m, double wall_distance_m,
                                             double focal_px, cv::Point2d principal_point,
                                             const cv::Rect& band, bool lines_are_rows)
    : lines_are_rows_(lines_are_rows) {
  const int lines = lines_are_rows ? band.height : band.width;
  ratios_.resize(lines);
  for (int i = 0; i < lines; ++i) {
    // The ray through the line's pixel on the principal point's other coordinate, with unit
    // depth, so the distance along it to the wall is the depth Z.
    const double offset = lines_are_rows ? (band.y + i - principal_point.y) / focal_px
                                         : (band.x + i - principal_point.x) / focal_px;
    const Eigen::Vector3d ray_cam =
        lines_are_rows ? Eigen::Vector3d(0.0, offset, 1.0) : Eigen::Vector3d(offset, 0.0, 1.0);
    const std::optional<double> depth = RayToWall(
        start_world_from_cam.translation(), start_world_from_cam.linear() * ray_cam, radius_m);
    // A forward ray from inside the pipe always leaves it ahead of the camera.
    CV_Assert(depth && *depth > 0.0);
    ratios_[i] = wall_distance_m / *depth;
  }
}

double ForeshorteningProfile::AxialScaleRatio(const cv::Mat& reference) const {
  CV_Assert(reference.type() == CV_32F);
  double weighted = 0.0, total = 0.0;
  // Each line's energy of the gradient along the pipe: differences along the line.
  for (int i = 0; i < static_cast<int>(ratios_.size()); ++i) {
    double energy = 0.0;
    if (lines_are_rows_) {
      const float* row = reference.ptr<float>(i);
      for (int x = 1; x < reference.cols; ++x) {
        const double d = row[x] - row[x - 1];
        energy += d * d;
      }
    } else {
      for (int y = 1; y < reference.rows; ++y) {
        const double d = reference.at<float>(y, i) - reference.at<float>(y - 1, i);
        energy += d * d;
      }
    }
    weighted += energy * ratios_[i];
    total += energy;
  }
  return total > 0.0 ? weighted / total : 1.0;
}

}  // namespace pipescope
