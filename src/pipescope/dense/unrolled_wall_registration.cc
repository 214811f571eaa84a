#include "pipescope/dense/unrolled_wall_registration.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <opencv2/imgproc.hpp>

#include "pipescope/util/error.h"

namespace pipescope {
namespace {

// Where a ray from inside the pipe meets the wall, as (h, s = r phi) with phi from +X towards
// +Y, unwrapped to lie within pi of `phi_reference`. False for a ray along the axis.
bool WallCoordinates(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double radius,
                     double phi_reference, double* h, double* s) {
  const std::optional<double> t = RayToWall(origin, direction, radius);
  if (!t) return false;
  const Eigen::Vector3d point = origin + *t * direction;
  double phi = std::atan2(point.y(), point.x());
  phi += 2.0 * std::numbers::pi * std::round((phi_reference - phi) / (2.0 * std::numbers::pi));
  *h = point.z();
  *s = radius * phi;
  return true;
}

bool AllValid(const cv::Mat& map_x, const cv::Rect& rect) {
  const cv::Mat inside = map_x(rect) >= 0.0f;
  return cv::countNonZero(inside) == rect.area();
}

}  // namespace

Eigen::Isometry3d PipeAxisMotion(const Eigen::Isometry3d& start_world_from_cam, double travel_m,
                                 double roll_rad) {
  Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
  motion.linear() = Eigen::AngleAxisd(roll_rad, Eigen::Vector3d::UnitZ()).matrix();
  motion.translation() = Eigen::Vector3d(0.0, 0.0, travel_m);
  return motion * start_world_from_cam;
}

UnrolledWallRegistration::UnrolledWallRegistration(const Camera& camera,
                                                   const Eigen::Isometry3d& start_world_from_cam,
                                                   double radius_m, double pixel_m, int downsample,
                                                   int margin_cells) {
  const Eigen::Vector3d origin = start_world_from_cam.translation();
  const Eigen::Vector3d optical_axis = start_world_from_cam.linear().col(2);
  double h_centre = 0, s_centre = 0;
  const double phi_axis = std::atan2(optical_axis.y(), optical_axis.x());
  if (!WallCoordinates(origin, optical_axis, radius_m, phi_axis, &h_centre, &s_centre)) {
    throw InputError(
        "dense-unrolled: the camera's optical axis runs along the pipe; it needs a "
        "camera that looks at the wall");
  }
  // The footprint's extent from the image border's rays.
  double h_min = h_centre, h_max = h_centre, s_min = s_centre, s_max = s_centre;
  const int w = camera.Width(), hgt = camera.Height();
  for (int k = 0; k <= 200; ++k) {
    const double f = k / 200.0;
    for (const Eigen::Vector2d& pixel :
         {Eigen::Vector2d(f * (w - 1), 0), Eigen::Vector2d(f * (w - 1), hgt - 1),
          Eigen::Vector2d(0, f * (hgt - 1)), Eigen::Vector2d(w - 1, f * (hgt - 1))}) {
      Eigen::Vector3d bearing;
      if (!camera.Unproject(pixel, &bearing)) continue;
      double h, s;
      if (!WallCoordinates(origin, start_world_from_cam.linear() * bearing, radius_m,
                           s_centre / radius_m, &h, &s)) {
        continue;
      }
      h_min = std::min(h_min, h), h_max = std::max(h_max, h);
      s_min = std::min(s_min, s), s_max = std::max(s_max, s);
    }
  }
  // At most one turn around the pipe.
  const double half_turn = std::numbers::pi * radius_m;
  s_min = std::max(s_min, s_centre - half_turn), s_max = std::min(s_max, s_centre + half_turn);
  UnrolledGrid full;
  full.radius_m = radius_m;
  full.pixel_m = pixel_m;
  const int half_u =
      static_cast<int>(std::ceil(std::max(h_max - h_centre, h_centre - h_min) / pixel_m));
  const int half_v =
      static_cast<int>(std::ceil(std::max(s_max - s_centre, s_centre - s_min) / pixel_m));
  full.size = cv::Size(2 * half_u + 1, 2 * half_v + 1);
  full.h0_m = h_centre - half_u * pixel_m;
  full.s0_m = s_centre - half_v * pixel_m;
  cv::Mat map_x, map_y;
  BuildUnrollingMaps(camera, start_world_from_cam, full, &map_x, &map_y);

  // Shrink a centred rectangle of the footprint's aspect until every cell is seen.
  cv::Rect rect;
  for (double scale = 1.0; scale > 0.05; scale -= 0.01) {
    const int ru = static_cast<int>(scale * half_u), rv = static_cast<int>(scale * half_v);
    rect = cv::Rect(half_u - ru, half_v - rv, 2 * ru + 1, 2 * rv + 1);
    if (AllValid(map_x, rect)) break;
    rect = cv::Rect();
  }
  rect.x += margin_cells, rect.y += margin_cells;
  rect.width -= 2 * margin_cells, rect.height -= 2 * margin_cells;
  if (rect.width < 16 || rect.height < 16) {
    throw InputError("dense-unrolled: the camera sees too little of the wall to register on it");
  }
  grid_ = full;
  grid_.size = rect.size();
  grid_.h0_m = full.h0_m + rect.x * pixel_m;
  grid_.s0_m = full.s0_m + rect.y * pixel_m;
  // Full-resolution pixel x is (x + 0.5) / factor - 0.5 in the box-filtered frame.
  const double factor = downsample;
  map_x_ = (map_x(rect) + 0.5) / factor - 0.5;
  map_y_ = (map_y(rect) + 0.5) / factor - 0.5;
}

cv::Mat UnrolledWallRegistration::Unroll(const cv::Mat& filtered_frame) const {
  cv::Mat unrolled;
  cv::remap(filtered_frame, unrolled, map_x_, map_y_, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  return unrolled;
}

}  // namespace pipescope
