#pragma once

#include <ceres/ceres.h>

#include <string>

namespace pipescope {

struct LeastSquaresOutcome {
  bool usable = false;  // Ceres' IsSolutionUsable()
  // Root mean square of the residual values before and after, without the robust losses.
  double initial_rms = 0.0;
  double final_rms = 0.0;
  // The block sizes Ceres' Schur elimination ran with ("2,3,d": residual rows, eliminated
  // block, other blocks; "d,d,d" is its slowest, all-dynamic kernel). Empty for other solvers.
  std::string schur_structure;
  int iterations = 0;  // Levenberg-Marquardt steps taken, successful or not
};

// Every nonlinear least-squares problem of the estimators is solved here: Ceres'
// Levenberg-Marquardt, quiet, on `num_threads` threads (one by default: the pipelines' second
// thread reads frames or runs the odometry). `observations`: the number of two-value (pixel)
// residual blocks the RMS is taken over, 0 for no RMS.
LeastSquaresOutcome SolveLeastSquares(ceres::Problem* problem,
                                      ceres::LinearSolverType linear_solver, int max_iterations,
                                      int observations, int num_threads = 1);

}  // namespace pipescope
