#include "pipescope/image/foreshortening.h"

#include <algorithm>
#include <optional>

#include "pipescope/image/wall_unrolling.h"

namespace pipescope {

std::vector<double> WallDepthRatios(const Eigen::Isometry3d& start_world_from_cam, double radius_m,
                                    double wall_distance_m, double focal_px,
                                    cv::Point2d principal_point, int line_count,
                                    bool lines_are_rows) {
  std::vector<double> ratios(line_count);
  for (int i = 0; i < line_count; ++i) {
    // The ray through the line's pixel on the principal point's other coordinate, with unit
    // depth, so the distance along it to the wall is the depth Z.
    const double offset = (i - (lines_are_rows ? principal_point.y : principal_point.x)) / focal_px;
    const Eigen::Vector3d ray_cam =
        lines_are_rows ? Eigen::Vector3d(0.0, offset, 1.0) : Eigen::Vector3d(offset, 0.0, 1.0);
    const std::optional<double> depth = RayToWall(
        start_world_from_cam.translation(), start_world_from_cam.linear() * ray_cam, radius_m);
    // A forward ray from inside the pipe always leaves it ahead of the camera.
    CV_Assert(depth && *depth > 0.0);
    ratios[i] = wall_distance_m / *depth;
  }
  return ratios;
}

AxialScaleEqualisation EqualiseAxialScale(const std::vector<double>& ratios, int first_line,
                                          int band_lines, bool lines_are_rows) {
  CV_Assert(first_line >= 0 && band_lines > 0 &&
            first_line + band_lines <= static_cast<int>(ratios.size()));
  AxialScaleEqualisation equalisation;
  equalisation.axial_ratio =
      *std::max_element(ratios.begin() + first_line, ratios.begin() + first_line + band_lines);
  equalisation.stretch.along_x = lines_are_rows;
  equalisation.stretch.factors.resize(ratios.size());
  // Lines outside the band that see the wall nearer than the band's edge keep their scale, so
  // that they still sample inside the frame (the image-space mosaic shows them).
  for (std::size_t i = 0; i < ratios.size(); ++i) {
    equalisation.stretch.factors[i] = std::min(1.0, ratios[i] / equalisation.axial_ratio);
  }
  return equalisation;
}

}  // namespace pipescope
