#pragma once

#include <vector>

#include "pipescope/eval/metrics.h"
#include "pipescope/io/junctions.h"
#include "pipescope/io/trajectory.h"

namespace pipescope {

// Ground-truth camera position at time `t`, linearly interpolated between the bracketing
// poses and clamped to the first or last pose outside the trajectory's time span.
Eigen::Vector3d InterpolatePosition(const Trajectory& ground_truth, double t);

// Matches each estimated junction to the scene junction nearest the ground-truth camera position
// at the estimated junction's timestamp, then compares every pair (i < j, in the order of
// `estimated_junctions`) of matched junctions (001 Table I). When two estimated junctions match
// the same scene junction, the one passed closer to it is kept and a warning logged. Throws
// InputError when the ground truth or the scene has no poses or junctions and there is an
// estimated junction to match, or an estimated junction has no timestamp.
std::vector<JunctionDistance> EvaluateJunctionDistances(
    const Trajectory& ground_truth, const std::vector<Junction>& scene_junctions,
    const std::vector<Junction>& estimated_junctions);

}  // namespace pipescope
