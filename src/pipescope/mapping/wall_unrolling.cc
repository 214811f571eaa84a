#include "pipescope/mapping/wall_unrolling.h"

#include <algorithm>
#include <cmath>
#include <opencv2/core/utility.hpp>
#include <vector>

namespace pipescope {

Eigen::Vector3d UnrolledGrid::WallPoint(double u, double v) const {
  const double phi = (s0_m + v * pixel_m) / radius_m;
  return {radius_m * std::cos(phi), radius_m * std::sin(phi), h0_m + u * pixel_m};
}

std::optional<double> RayToWall(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                                double radius_m) {
  const double a = direction.head<2>().squaredNorm();
  if (a < 1e-12) return std::nullopt;
  const double b = origin.head<2>().dot(direction.head<2>());
  const double c = origin.head<2>().squaredNorm() - radius_m * radius_m;  // < 0 inside
  const double discriminant = b * b - a * c;
  if (discriminant < 0.0) return std::nullopt;
  const double t = (-b + std::sqrt(discriminant)) / a;
  if (t <= 0.0) return std::nullopt;
  return t;
}

void BuildUnrollingMaps(const Camera& camera, const Eigen::Isometry3d& world_from_cam,
                        const UnrolledGrid& grid, cv::Mat* map_x, cv::Mat* map_y) {
  CV_Assert(grid.radius_m > 0 && grid.pixel_m > 0 && grid.size.width >= 0 && grid.size.height >= 0);
  map_x->create(grid.size, CV_32F);
  map_y->create(grid.size, CV_32F);
  const Eigen::Isometry3d cam_from_world = world_from_cam.inverse();
  const Eigen::Matrix3d rotation = cam_from_world.linear();
  // Along a row only h changes, so the camera-frame point moves by a constant step per column.
  const Eigen::Vector3d step = rotation.col(2) * grid.pixel_m;
  cv::parallel_for_(cv::Range(0, grid.size.height), [&](const cv::Range& rows) {
    for (int v = rows.start; v < rows.end; ++v) {
      float* xs = map_x->ptr<float>(v);
      float* ys = map_y->ptr<float>(v);
      const Eigen::Vector3d row_start = cam_from_world * grid.WallPoint(0.0, v);
      for (int u = 0; u < grid.size.width; ++u) {
        const Eigen::Vector3d point_cam = row_start + u * step;
        Eigen::Vector2d pixel;
        if (camera.Project(point_cam, &pixel) == ProjectionStatus::kValid) {
          xs[u] = static_cast<float>(pixel.x());
          ys[u] = static_cast<float>(pixel.y());
        } else {
          xs[u] = -1.0f;
          ys[u] = -1.0f;
        }
      }
    }
  });
}

cv::Mat UnrollFrame(const cv::Mat& frame, const cv::Mat& map_x, const cv::Mat& map_y,
                    cv::Mat* valid_mask) {
  CV_Assert(frame.channels() == 1 && map_x.type() == CV_32F && map_y.type() == CV_32F &&
            map_x.size() == map_y.size());
  cv::Mat image;
  if (frame.type() == CV_32F) {
    image = frame;
  } else {
    frame.convertTo(image, CV_32F);
  }
  cv::Mat result(map_x.size(), CV_32F);
  cv::Mat mask(map_x.size(), CV_8U);
  const float max_x = static_cast<float>(image.cols - 1);
  const float max_y = static_cast<float>(image.rows - 1);
  // The top-left tap stops one short of the last column / row, so at x == width - 1 the right
  // tap is still inside (with weight 0).
  const int last_x0 = std::max(0, image.cols - 2);
  const int last_y0 = std::max(0, image.rows - 2);
  cv::parallel_for_(cv::Range(0, map_x.rows), [&](const cv::Range& rows) {
    for (int v = rows.start; v < rows.end; ++v) {
      const float* xs = map_x.ptr<float>(v);
      const float* ys = map_y.ptr<float>(v);
      float* out = result.ptr<float>(v);
      uchar* valid = mask.ptr<uchar>(v);
      for (int u = 0; u < map_x.cols; ++u) {
        const float x = xs[u];
        const float y = ys[u];
        out[u] = 0.0f;
        valid[u] = 0;
        // The -1 of an invalid cell fails this test too.
        if (!(x >= 0.0f && y >= 0.0f && x <= max_x && y <= max_y)) continue;
        const int x0 = std::min(static_cast<int>(x), last_x0);
        const int y0 = std::min(static_cast<int>(y), last_y0);
        const int x1 = std::min(x0 + 1, image.cols - 1);
        const int y1 = std::min(y0 + 1, image.rows - 1);
        const float fx = x - x0;
        const float fy = y - y0;
        const float* top = image.ptr<float>(y0);
        const float* bottom = image.ptr<float>(y1);
        const float value = (1.0f - fy) * ((1.0f - fx) * top[x0] + fx * top[x1]) +
                            fy * ((1.0f - fx) * bottom[x0] + fx * bottom[x1]);
        if (!std::isfinite(value)) continue;
        out[u] = value;
        valid[u] = 255;
      }
    }
  });
  if (valid_mask != nullptr) *valid_mask = mask;
  return result;
}

}  // namespace pipescope
