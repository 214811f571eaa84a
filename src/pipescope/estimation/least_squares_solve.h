#pragma once

#include <ceres/ceres.h>

namespace pipescope {

struct LeastSquaresOutcome {
  bool usable = false;  // Ceres' IsSolutionUsable()
  // Root mean square of the residual values before and after, without the robust losses.
  double initial_rms = 0.0;
  double final_rms = 0.0;
};

// Solves `problem` with Ceres' Levenberg-Marquardt on one thread (the pipeline's second thread
// reads frames). `observations`: the number of two-value (pixel) residual blocks the RMS is
// taken over, 0 for no RMS.
LeastSquaresOutcome SolveLeastSquares(ceres::Problem* problem,
                                      ceres::LinearSolverType linear_solver, int max_iterations,
                                      int observations);

}  // namespace pipescope
