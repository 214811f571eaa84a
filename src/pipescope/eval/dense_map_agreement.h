#pragma once

#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <vector>

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

// Where one row of a grid goes into the scene (`scene_from_map`), and the point inside the pipe
// (scene frame) its cells are looked at from.
struct GridRowPlacement {
  Eigen::Isometry3d scene_from_map = Eigen::Isometry3d::Identity();
  Eigen::Vector3d viewpoint = Eigen::Vector3d::Zero();
};

// The albedo under each cell of `grid` as the simulator renders it: the wall point where the
// ray from its row's viewpoint through the cell's point, taken into the scene by its row's
// placement (`rows`, one per grid row), leaves the pipe, filtered to the grid's spacing. CV_32F,
// NaN where the ray leaves through an open end, or meets the wall farther than `max_miss_m` from
// the cell's point: there the map's cylinder has no wall (a T's opening into the other pipe),
// and what the map shows is seen through it from elsewhere. Throws InputError unless there is a
// placement per row.
cv::Mat SimulatedAlbedoUnderGrid(const DenseMapGrid& grid,
                                 const std::vector<GridRowPlacement>& rows,
                                 const Simulation& simulation, double max_miss_m);

// Correlates the high-passed map `grey` (CV_8U or CV_32F on `grid`; 0 or NaN where no key frame
// saw the cell) with the high-passed `albedo` (SimulatedAlbedoUnderGrid) over the cells seen
// where the albedo is defined, at the best shift. Each grid is high-passed by normalised
// convolution over those of its cells (the map's: seen and over the wall), so neither the
// unseen border nor what a T's opening shows adds an edge. Throws InputError when the sizes differ
// from the grid's or the options are out of range; the correlation is NaN when fewer than 100 cells
// overlap.
DenseMapAgreement CorrelateWithAlbedo(const cv::Mat& grey, const cv::Mat& albedo,
                                      const DenseMapGrid& grid,
                                      const DenseMapAgreementOptions& options = {});

}  // namespace pipescope
