#include "pipescope/mapping/unrolled_mosaic.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace pipescope {

UnrolledMosaic::UnrolledMosaic(const Camera& camera, double radius_m, double pixel_m,
                               double h_min_m, double h_max_m, const UnrolledMosaicOptions& options)
    : camera_(camera),
      max_axial_range_m_(options.max_axial_range_m > 0 ? options.max_axial_range_m
                                                       : 3.0 * radius_m),
      footprint_samples_(std::max(2, options.footprint_samples)),
      map_lattice_cells_(std::max(1, options.map_lattice_cells)) {
  if (!(radius_m > 0) || !(pixel_m > 0) || !(h_max_m >= h_min_m) || !std::isfinite(h_min_m) ||
      !std::isfinite(h_max_m)) {
    throw std::invalid_argument("UnrolledMosaic: needs radius > 0, pixel > 0, h_max >= h_min");
  }
  grid_.radius_m = radius_m;
  grid_.h0_m = h_min_m;
  grid_.s0_m = 0.0;
  grid_.pixel_m = pixel_m;
  grid_.size.width = static_cast<int>(std::floor((h_max_m - h_min_m) / pixel_m + 1e-9)) + 1;
  grid_.size.height = static_cast<int>(std::ceil(2.0 * M_PI * radius_m / pixel_m - 1e-9));
}

bool UnrolledMosaic::Footprint(const Eigen::Isometry3d& world_from_cam, cv::Range* columns,
                               cv::Range* rows) const {
  const Eigen::Vector3d centre = world_from_cam.translation();
  const double radius = grid_.radius_m;
  const double h_lo = centre.z() - max_axial_range_m_;
  const double h_hi = centre.z() + max_axial_range_m_;
  double min_h = h_hi, max_h = h_lo;
  std::vector<double> phis;
  // Where the ray of a pixel leaves the pipe, clamped to the axial range.
  const auto sample = [&](double x, double y) {
    Eigen::Vector3d bearing;
    if (!camera_.Unproject({x, y}, &bearing)) return;
    const Eigen::Vector3d direction = world_from_cam.linear() * bearing;
    const std::optional<double> t = RayToWall(centre, direction, radius);
    if (!t) {
      // Along the axis: reaches the end of the range without meeting the wall.
      const double h = direction.z() >= 0 ? h_hi : h_lo;
      min_h = std::min(min_h, h);
      max_h = std::max(max_h, h);
      return;
    }
    const Eigen::Vector3d hit = centre + *t * direction;
    const double h = std::clamp(hit.z(), h_lo, h_hi);
    min_h = std::min(min_h, h);
    max_h = std::max(max_h, h);
    phis.push_back(std::atan2(hit.y(), hit.x()));
  };
  const int n = footprint_samples_;
  const double width = camera_.Width() - 1, height = camera_.Height() - 1;
  for (int i = 0; i <= n; ++i) {
    const double fi = static_cast<double>(i) / n;
    for (int j = 0; j <= n; ++j) sample(fi * width, static_cast<double>(j) / n * height);
  }
  if (phis.empty() || max_h < min_h) return false;

  // The footprint's arc around the pipe: the complement of the largest gap between samples.
  std::sort(phis.begin(), phis.end());
  double largest_gap = 2.0 * M_PI - (phis.back() - phis.front());
  double arc_start = phis.front();
  for (std::size_t i = 1; i < phis.size(); ++i) {
    if (phis[i] - phis[i - 1] > largest_gap) {
      largest_gap = phis[i] - phis[i - 1];
      arc_start = phis[i];
    }
  }
  const double arc = 2.0 * M_PI - largest_gap;

  // Between samples the footprint may bulge a little past them: a margin of 5 % and 2 cells.
  const double pixel = grid_.pixel_m;
  const double h_margin = 0.05 * (max_h - min_h) + 2.0 * pixel;
  const int u_begin =
      std::max(0, static_cast<int>(std::floor((min_h - h_margin - grid_.h0_m) / pixel)));
  const int u_end = std::min(
      grid_.size.width, static_cast<int>(std::ceil((max_h + h_margin - grid_.h0_m) / pixel)) + 1);
  if (u_end <= u_begin) return false;
  *columns = cv::Range(u_begin, u_end);

  const double s_margin = 0.05 * arc * radius + 2.0 * pixel;
  const int v_begin = static_cast<int>(std::floor((arc_start * radius - s_margin) / pixel));
  const int v_end =
      static_cast<int>(std::ceil(((arc_start + arc) * radius + s_margin) / pixel)) + 1;
  // Sparse samples all around (a forward view): the whole circumference.
  if (largest_gap < M_PI / 8 || v_end - v_begin >= grid_.size.height) {
    *rows = cv::Range(0, grid_.size.height);
  } else {
    *rows = cv::Range(v_begin, v_end);
  }
  return true;
}

void UnrolledMosaic::Add(const cv::Mat& frame, const Eigen::Isometry3d& world_from_cam) {
  CV_Assert(frame.channels() == 1 && frame.cols == camera_.Width() &&
            frame.rows == camera_.Height());
  ++frames_added_;
  cv::Range columns, rows;
  if (!Footprint(world_from_cam, &columns, &rows)) return;
  const int height = grid_.size.height;
  // The rows may wrap around s = 0: one piece of grid per side of the seam.
  for (int v = rows.start; v < rows.end;) {
    const int wrapped = ((v % height) + height) % height;
    const int count = std::min(rows.end - v, height - wrapped);
    UnrolledGrid piece = grid_;
    piece.h0_m = grid_.h0_m + columns.start * grid_.pixel_m;
    piece.s0_m = wrapped * grid_.pixel_m;
    piece.size = cv::Size(columns.size(), count);
    cv::Mat map_x, map_y, valid;
    BuildUnrollingMaps(camera_, world_from_cam, piece, &map_x, &map_y, map_lattice_cells_);
    const cv::Mat values = UnrollFrame(frame, map_x, map_y, &valid);
    accumulator_.Add(values, cv::Point(columns.start, wrapped), valid);
    v += count;
  }
}

cv::Mat UnrolledMosaic::Render() const { return Render(cv::Rect(cv::Point(0, 0), grid_.size)); }

cv::Mat UnrolledMosaic::Render(const cv::Rect& region) const { return accumulator_.Render(region); }

}  // namespace pipescope
