#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <optional>

#include "pipescope/camera/camera.h"
#include "pipescope/geometry/pipe_cylinder.h"

namespace pipescope {

// The unrolled wall of a straight pipe whose axis is the world Z axis (GUIDE §3): a wall point
// is (r cos phi, r sin phi, h), phi measured from +X towards +Y. The grid samples the surface
// coordinates (h, s = r phi) of 000 §6.1 / Fig. 15 at a square cell of pixel_m metres: column
// u <-> h = h0_m + u * pixel_m, row v <-> s = s0_m + v * pixel_m. s may leave [0, 2 pi r); it
// wraps around the pipe.
struct UnrolledGrid {
  double radius_m = 0;
  double h0_m = 0;
  double s0_m = 0;
  double pixel_m = 0;
  cv::Size size;

  // World point of the (fractional) cell (u, v).
  Eigen::Vector3d WallPoint(double u, double v) const;
};

// Remap tables (CV_32F, grid size) for cv::remap: for each grid cell, the pixel of a frame of
// `camera` taken at `world_from_cam` that sees the cell's wall point; -1 in both tables where
// the point is behind the camera, beyond the model's valid angle or off the image. A camera
// inside the pipe sees every wall point it points at (the interior of a cylinder is convex), so
// there is no occlusion test.
//
// lattice_cells > 1 projects only every lattice_cells-th cell along both axes (the lattice's
// nodes) and interpolates the pixel bilinearly inside each block whose four corner nodes all
// lie on the image and within 6 px of each other; blocks wholly beyond one edge of the image
// are unseen, and the others are projected cell by cell. The map bends slowly (the wall's
// curvature, the lens's distortion): for the steel-6in camera at its ground resolution the
// pixels differ from the exact ones by at most 0.0028 px at 4 cells (LatticeMaps tests).
void BuildUnrollingMaps(const Camera& camera, const Eigen::Isometry3d& world_from_cam,
                        const UnrolledGrid& grid, cv::Mat* map_x, cv::Mat* map_y,
                        int lattice_cells = 1);

// Resamples `frame` (one channel, converted to CV_32F) onto the grid of the maps by exact
// bilinear interpolation (no cv::remap weight quantisation). `valid_mask` (CV_8U, may be null)
// is 255 where the sample lies in [0, width - 1] x [0, height - 1], so all four bilinear taps
// are inside the frame; the result is 0 elsewhere. Frame pixels that are not finite make the
// cells that tap them invalid.
cv::Mat UnrollFrame(const cv::Mat& frame, const cv::Mat& map_x, const cv::Mat& map_y,
                    cv::Mat* valid_mask);

}  // namespace pipescope
