#include "pipescope/estimation/least_squares_solve.h"

#include <cmath>

namespace pipescope {
namespace {

// 0.5 sum r^2 over `observations` pairs of values: sqrt(cost / observations) is the RMS of a value.
double UnrobustRms(ceres::Problem* problem, int observations) {
  if (observations <= 0) return 0.0;
  ceres::Problem::EvaluateOptions evaluate;
  evaluate.apply_loss_function = false;
  double cost = 0.0;
  problem->Evaluate(evaluate, &cost, nullptr, nullptr, nullptr);
  return std::sqrt(cost / observations);
}

}  // namespace

LeastSquaresOutcome SolveLeastSquares(ceres::Problem* problem,
                                      ceres::LinearSolverType linear_solver, int max_iterations,
                                      int observations, int num_threads) {
  LeastSquaresOutcome outcome;
  outcome.initial_rms = UnrobustRms(problem, observations);
  ceres::Solver::Options solver;
  solver.linear_solver_type = linear_solver;
  solver.max_num_iterations = max_iterations;
  solver.num_threads = num_threads;
  solver.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, problem, &summary);
  outcome.final_rms = UnrobustRms(problem, observations);
  outcome.usable = summary.IsSolutionUsable();
  outcome.schur_structure = summary.schur_structure_used;
  outcome.iterations = summary.num_successful_steps + summary.num_unsuccessful_steps;
  return outcome;
}

}  // namespace pipescope
