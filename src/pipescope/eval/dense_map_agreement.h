#pragma once

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pipescope/eval/metrics.h"
#include "pipescope/mapping/dense_appearance_map.h"
#include "pipescope/synthetic/simulation.h"

namespace pipescope {

// How well a dense appearance map (001 §IV-B) follows the simulated wall's albedo: issue 23
// asks for a correlation of at least 0.8 after a high-pass on the straight sections.
struct DenseMapAgreementOptions {
  // Both grids have a Gaussian of this sigma subtracted before they are correlated: the LEDs'
  // shading and the exposure, which no map of grey values removes, are broader.
  double high_pass_sigma_m = 0.02;
  // The map is registered to the albedo by the whole-cell shift (rows along the axis, columns
  // around it) within this many cells that correlates best: what is measured is the map's
  // appearance, not the odometry's drift of a few millimetres, which the trajectory's metrics
  // measure.
  int max_shift_cells = 8;
};


// The albedo under each cell of `grid` as the simulator renders it: the wall point where the
// ray from `viewpoint` (scene frame, inside the pipe) through the cell's point, taken into the
// scene by `scene_from_map`, leaves the pipe, filtered to the grid's spacing. CV_32F, NaN
// where the ray leaves through an open end.
cv::Mat SimulatedAlbedoUnderGrid(const DenseMapGrid& grid, const Eigen::Isometry3d& scene_from_map,
                                 const Eigen::Vector3d& viewpoint, const Simulation& simulation);

// Correlates the high-passed map `grey` (CV_8U or CV_32F on `grid`; 0 or NaN where no key frame
// saw the cell) with the high-passed `albedo` (SimulatedAlbedoUnderGrid) over the cells seen,
// at the best shift. Each grid is high-passed by normalised convolution over its own valid
// cells, so the unseen border adds no edge. Throws InputError when the sizes differ from the
// grid's or the options are out of range; the correlation is NaN when fewer than 100 cells
// overlap.
DenseMapAgreement CorrelateWithAlbedo(const cv::Mat& grey, const cv::Mat& albedo,
                                      const DenseMapGrid& grid,
                                      const DenseMapAgreementOptions& options = {});

}  // namespace pipescope
