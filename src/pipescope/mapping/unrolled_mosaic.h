#pragma once

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pipescope/camera/camera.h"
#include "pipescope/image/wall_unrolling.h"
#include "pipescope/mapping/mean_accumulator.h"

namespace pipescope {

struct UnrolledMosaicOptions {
  // Wall seen farther than this along the axis from the camera is left out: a forward-looking
  // camera sees the wall far down the pipe at a footprint much coarser than the mosaic's
  // cells, which would blur the mean. 0 = three pipe radii, more than a wall-looking camera
  // ever sees.
  double max_axial_range_m = 0.0;
  // Pixels of the frame sampled (per side, and as an interior grid) to find the part of the
  // wall it sees; only cells there are projected.
  int footprint_samples = 48;
  // The unrolling maps are projected exactly every this many cells and interpolated between
  // (BuildUnrollingMaps' lattice_cells); 1 projects every cell. Projecting every cell of a
  // 1024x768 frame's footprint was most of the time of the mosaic.
  int map_lattice_cells = 4;
};

// The unrolled appearance map of a straight pipe on its surface (000 §6.1, Fig. 15 and 17): a
// cell (u, v) is the wall point at h = h_min_m + u * pixel_m, s = r phi = v * pixel_m (the
// UnrolledGrid conventions), and holds the mean of the gain-corrected frames that see it.
class UnrolledMosaic {
 public:
  // Rows cover s in [0, 2 pi r) (ceil(2 pi r / pixel_m) of them), columns h in
  // [h_min_m, h_max_m].
  UnrolledMosaic(const Camera& camera, double radius_m, double pixel_m, double h_min_m,
                 double h_max_m, const UnrolledMosaicOptions& options = {});

  // Adds a frame (one channel, converted to CV_32F; non-finite pixels are left out) taken at
  // `world_from_cam` to every cell it sees within the axial range.
  void Add(const cv::Mat& frame, const Eigen::Isometry3d& world_from_cam);

  // The whole map (CV_32F, grid size), NaN where no frame contributed.
  cv::Mat Render() const;
  // Part of the map, e.g. CoveredRegion(): a pipe 20 m long at 0.2 mm cells is 100 000
  // columns, of which a wall-looking camera covers a band of a few hundred rows.
  cv::Mat Render(const cv::Rect& region) const;
  // The smallest rectangle of cells holding every contribution; empty before any.
  cv::Rect CoveredRegion() const { return accumulator_.Bounds(); }

  // The whole map's grid (h0_m = h_min_m, s0_m = 0).
  const UnrolledGrid& grid() const { return grid_; }
  int frames_added() const { return frames_added_; }

 private:
  // The cells (columns, and rows before wrapping around the pipe) the frame may see.
  bool Footprint(const Eigen::Isometry3d& world_from_cam, cv::Range* columns,
                 cv::Range* rows) const;

  const Camera& camera_;
  UnrolledGrid grid_;
  double max_axial_range_m_;
  int footprint_samples_;
  int map_lattice_cells_;
  MeanAccumulator accumulator_;
  int frames_added_ = 0;
};

}  // namespace pipescope
