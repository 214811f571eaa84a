#pragma once

#include <ceres/ceres.h>

namespace pipescope {

// Solves a small least-squares problem quietly with dense QR (cylinder fits, pose-only
// refinements): the solver settings these share, in one place.
inline ceres::Solver::Summary SolveSmallProblem(ceres::Problem* problem, int max_iterations) {
  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::DENSE_QR;
  solver_options.max_num_iterations = max_iterations;
  solver_options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, problem, &summary);
  return summary;
}

}  // namespace pipescope
