#pragma once

#include <cstddef>
#include <vector>

#include "pipescope/io/trajectory.h"

namespace pipescope {

// Indices of one ground-truth pose and the estimated pose taken at (nearly) the same time.
struct AssociatedPair {
  std::size_t gt_index;
  std::size_t est_index;
};

// Each estimated pose is matched to the nearest ground-truth timestamp within max_dt_s. When
// several estimated poses share the same nearest ground-truth pose, only the closest in time
// keeps it, so the pairs are one-to-one; they come in time order, increasing in both indices.
// Both trajectories must have non-decreasing timestamps (ReadTumTrajectory guarantees it);
// throws std::invalid_argument otherwise.
std::vector<AssociatedPair> AssociateByTimestamp(const Trajectory& ground_truth,
                                                 const Trajectory& estimate,
                                                 double max_dt_s = 0.01);

}  // namespace pipescope
