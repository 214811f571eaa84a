#pragma once

#include <vector>

#include "pipescope/estimation/track_statistics.h"

namespace pipescope {

// The 1-DOF motion of 000 §5.3.1: the new key frame is the last one moved by delta_h along the
// pipe axis (eq. 40), chosen to minimise eq. 42-44 against the statistics S(g) of the points it
// sees again.
struct AxialStepOptions {
  // Huber threshold (metres) on a point's distance from its track's mean, by iteratively
  // reweighted least squares. 0 = plain least squares, as 000.
  double huber_m = 0.0005;
  int iterations = 5;
};

// One point of the new key frame: where it lands on the wall with delta_h = 0, and the
// statistics of its track (n > 0).
struct AxialStepObservation {
  SurfacePoint predicted;
  TrackStatistics track;
};

// A pure translation along the axis moves every wall point by the same delta_h and leaves rho
// unchanged, so eq. 42 is quadratic in delta_h with the exact minimum
//   delta_h = sum_g n_g (mean_h(g) - h_hat(g)) / sum_g n_g
// (Ceres would find the same number in one step). With a Huber threshold each track's weight is
// min(1, huber_m / d_g), d_g its surface distance from its mean after the step. Returns 0 for no
// observations. `inliers` (may be null) counts the tracks within the threshold.
double EstimateAxialStep(const std::vector<AxialStepObservation>& observations,
                         const AxialStepOptions& options, int* inliers = nullptr);

}  // namespace pipescope
