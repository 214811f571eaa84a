#include "pipescope/image/wall_unrolling.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <opencv2/core/utility.hpp>
#include <vector>

namespace pipescope {

Eigen::Vector3d UnrolledGrid::WallPoint(double u, double v) const {
  const double phi = (s0_m + v * pixel_m) / radius_m;
  return {radius_m * std::cos(phi), radius_m * std::sin(phi), h0_m + u * pixel_m};
}

namespace {

// The pixel that sees the camera-frame point, or (-1, -1) where the camera does not see it.
void ProjectOrMark(const Camera& camera, const Eigen::Vector3d& point_cam, float* x, float* y) {
  Eigen::Vector2d pixel;
  if (camera.Project(point_cam, &pixel) == ProjectionStatus::kValid) {
    *x = static_cast<float>(pixel.x());
    *y = static_cast<float>(pixel.y());
  } else {
    *x = -1.0f;
    *y = -1.0f;
  }
}

// Every cell projected on its own.
void BuildExactMaps(const Camera& camera, const Eigen::Isometry3d& cam_from_world,
                    const UnrolledGrid& grid, cv::Mat* map_x, cv::Mat* map_y) {
  // Along a row only h changes, so the camera-frame point moves by a constant step per column.
  const Eigen::Vector3d step = cam_from_world.linear().col(2) * grid.pixel_m;
  cv::parallel_for_(cv::Range(0, grid.size.height), [&](const cv::Range& rows) {
    for (int v = rows.start; v < rows.end; ++v) {
      float* xs = map_x->ptr<float>(v);
      float* ys = map_y->ptr<float>(v);
      const Eigen::Vector3d row_start = cam_from_world * grid.WallPoint(0.0, v);
      for (int u = 0; u < grid.size.width; ++u) {
        ProjectOrMark(camera, row_start + u * step, &xs[u], &ys[u]);
      }
    }
  });
}

// A lattice node: the pixel its wall point projects to, and whether the camera sees it there.
struct LatticeNode {
  Eigen::Vector2d pixel;
  ProjectionStatus status;
};

// Whether all four corners project beyond the same edge of the image by more than a pixel, so
// that the whole block between them does (the map bends by hundredths of a pixel over a block).
bool BlockOffImage(const Camera& camera, const std::array<const LatticeNode*, 4>& corners) {
  constexpr double kMarginPx = 1.0;
  const double low = -0.5 - kMarginPx;
  const double high_x = camera.Width() - 0.5 + kMarginPx;
  const double high_y = camera.Height() - 0.5 + kMarginPx;
  bool left = true, right = true, above = true, below = true;
  for (const LatticeNode* node : corners) {
    // Only off-image projections are trusted: beyond the model's valid angle the pixel may
    // fold back.
    if (node->status != ProjectionStatus::kOutsideImage) return false;
    left = left && node->pixel.x() < low;
    right = right && node->pixel.x() > high_x;
    above = above && node->pixel.y() < low;
    below = below && node->pixel.y() > high_y;
  }
  return left || right || above || below;
}

// A block is interpolated only while its corners lie this close together in the image: the
// interpolation error grows as the square of the block's size in pixels (0.003 px at 4 px on
// the steel-6in camera), so cells coarser than a pixel (a coarse mosaic) are projected one by
// one.
constexpr double kMaxBlockSpanPx = 6.0;

// The largest distance along x or y between the block's corners, in pixels; infinite when one
// has no pixel.
double BlockSpanPx(const std::array<const LatticeNode*, 4>& corners) {
  Eigen::Vector2d low = corners[0]->pixel, high = corners[0]->pixel;
  for (const LatticeNode* node : corners) {
    if (node->status == ProjectionStatus::kBehindCamera) return INFINITY;
    low = low.cwiseMin(node->pixel);
    high = high.cwiseMax(node->pixel);
  }
  return (high - low).maxCoeff();
}

// The nodes (every `step`-th cell, the last node at or past the last cell) projected exactly;
// every block of step x step cells between four nodes on the image interpolated, every block
// whose nodes all lie beyond one edge of the image unseen, and the rest projected cell by cell.
void BuildLatticeMaps(const Camera& camera, const Eigen::Isometry3d& cam_from_world,
                      const UnrolledGrid& grid, int step, cv::Mat* map_x, cv::Mat* map_y) {
  const int blocks_u = (grid.size.width + step - 1) / step;
  const int blocks_v = (grid.size.height + step - 1) / step;
  const int nodes_u = blocks_u + 1;
  std::vector<LatticeNode> nodes((blocks_v + 1) * nodes_u);
  for (int j = 0; j <= blocks_v; ++j) {
    for (int i = 0; i < nodes_u; ++i) {
      LatticeNode& node = nodes[j * nodes_u + i];
      node.status =
          camera.Project(cam_from_world * grid.WallPoint(i * step, j * step), &node.pixel);
    }
  }
  const Eigen::Vector3d cell_step = cam_from_world.linear().col(2) * grid.pixel_m;
  const float max_x = static_cast<float>(camera.Width() - 0.5);
  const float max_y = static_cast<float>(camera.Height() - 0.5);
  const float inverse_step = 1.0f / static_cast<float>(step);
  cv::parallel_for_(cv::Range(0, blocks_v), [&](const cv::Range& block_rows) {
    for (int j = block_rows.start; j < block_rows.end; ++j) {
      const int v_begin = j * step, v_end = std::min(v_begin + step, grid.size.height);
      for (int i = 0; i < blocks_u; ++i) {
        const int u_begin = i * step, u_end = std::min(u_begin + step, grid.size.width);
        const std::array<const LatticeNode*, 4> corners = {
            &nodes[j * nodes_u + i], &nodes[j * nodes_u + i + 1], &nodes[(j + 1) * nodes_u + i],
            &nodes[(j + 1) * nodes_u + i + 1]};
        const bool small = BlockSpanPx(corners) <= kMaxBlockSpanPx;
        const bool corners_seen =
            small && std::all_of(corners.begin(), corners.end(), [](auto node) {
              return node->status == ProjectionStatus::kValid;
            });
        const bool off_image = small && !corners_seen && BlockOffImage(camera, corners);
        for (int v = v_begin; v < v_end; ++v) {
          float* xs = map_x->ptr<float>(v);
          float* ys = map_y->ptr<float>(v);
          if (off_image) {
            std::fill(xs + u_begin, xs + u_end, -1.0f);
            std::fill(ys + u_begin, ys + u_end, -1.0f);
            continue;
          }
          if (!corners_seen) {
            const Eigen::Vector3d row_start = cam_from_world * grid.WallPoint(u_begin, v);
            for (int u = u_begin; u < u_end; ++u) {
              ProjectOrMark(camera, row_start + (u - u_begin) * cell_step, &xs[u], &ys[u]);
            }
            continue;
          }
          // Bilinear in the block: down the block's left and right edges, then along the row.
          const Eigen::Vector2f p00 = corners[0]->pixel.cast<float>();
          const Eigen::Vector2f p10 = corners[1]->pixel.cast<float>();
          const Eigen::Vector2f p01 = corners[2]->pixel.cast<float>();
          const Eigen::Vector2f p11 = corners[3]->pixel.cast<float>();
          const float b = (v - v_begin) * inverse_step;
          const Eigen::Vector2f left = p00 + b * (p01 - p00);
          const Eigen::Vector2f along = (p10 + b * (p11 - p10) - left) * inverse_step;
          for (int u = u_begin; u < u_end; ++u) {
            const float x = left.x() + (u - u_begin) * along.x();
            const float y = left.y() + (u - u_begin) * along.y();
            // The image's edge may bend between the nodes: the cells past it are unseen.
            const bool inside = x >= -0.5f && x <= max_x && y >= -0.5f && y <= max_y;
            xs[u] = inside ? x : -1.0f;
            ys[u] = inside ? y : -1.0f;
          }
        }
      }
    }
  });
}

}  // namespace

void BuildUnrollingMaps(const Camera& camera, const Eigen::Isometry3d& world_from_cam,
                        const UnrolledGrid& grid, cv::Mat* map_x, cv::Mat* map_y,
                        int lattice_cells) {
  CV_Assert(grid.radius_m > 0 && grid.pixel_m > 0 && grid.size.width >= 0 &&
            grid.size.height >= 0 && lattice_cells >= 1);
  map_x->create(grid.size, CV_32F);
  map_y->create(grid.size, CV_32F);
  if (grid.size.empty()) return;
  const Eigen::Isometry3d cam_from_world = world_from_cam.inverse();
  if (lattice_cells == 1) {
    BuildExactMaps(camera, cam_from_world, grid, map_x, map_y);
  } else {
    BuildLatticeMaps(camera, cam_from_world, grid, lattice_cells, map_x, map_y);
  }
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
