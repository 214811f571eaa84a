#pragma once

#include "pipescope/eval/alignment.h"
#include "pipescope/eval/metrics.h"
#include "pipescope/io/trajectory.h"

namespace pipescope {

struct EvaluationOptions {
  // Alignment before the absolute trajectory error; se3 suits metric methods.
  Alignment alignment = Alignment::kSe3;
  // Largest time difference (s) for a ground-truth and an estimated pose to be matched.
  double max_dt_s = 0.01;
  // Ground-truth path length of the relative pose error's segments (rpe_1m_pct).
  double rpe_segment_m = 1.0;
  // A run is out-and-back when its ground truth comes back from its farthest point (the
  // turnaround) at least this fraction of the way it went out, in straight lines. Before, it had
  // to end within 10 % of that distance from its start: a robot that came back 0.81 of its 1 m
  // was scored as a one-way run by its 0.19 m net displacement, a 20 % "error" of methods whose
  // legs were within 0.24 % (docs/conditions.md).
  double min_return_fraction = 0.5;
  // The path lengths (path_*_m) add the steps between frames where the ground truth advanced at
  // least this far, so that a method's frame-to-frame jitter does not lengthen its path (to first
  // order a step d with independent jitter sigma across the path grows by sigma^2 / d^2: 0.25 %
  // for 0.05 mm at 1 mm steps, 0.0006 % over 2 cm) while a turn of radius r is still followed to
  // (step / r)^2 / 24 (0.04 % at r = 0.2 m, 0.3 % in a 6-inch pipe's bend of r = 0.076 m).
  double path_step_m = 0.02;
};

// Evaluates `estimate` against `ground_truth` on the frames matched by timestamp: distance
// errors (000 eq. 50, 51), absolute trajectory error after alignment, relative pose error.
// Leaves junction_distances unset. Throws InputError when fewer than 2 frames match.
Metrics EvaluateTrajectory(const Trajectory& ground_truth, const Trajectory& estimate,
                           const EvaluationOptions& options);

// 100 |estimate - ground_truth| / ground_truth (000 eq. 50); unset when ground_truth is 0.
std::optional<double> PercentError(double ground_truth, double estimate);

}  // namespace pipescope
