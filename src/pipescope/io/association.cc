#include "pipescope/io/association.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pipescope {
namespace {

bool IsTimeSorted(const Trajectory& trajectory) {
  return std::is_sorted(
      trajectory.begin(), trajectory.end(),
      [](const StampedPose& a, const StampedPose& b) { return a.timestamp < b.timestamp; });
}

// Index of the ground-truth pose nearest in time to `t` (the earlier one on a tie). Monotone
// in `t`, which is what keeps the association free of crossings.
std::size_t NearestIndex(const Trajectory& ground_truth, double t) {
  const auto after =
      std::lower_bound(ground_truth.begin(), ground_truth.end(), t,
                       [](const StampedPose& pose, double time) { return pose.timestamp < time; });
  if (after == ground_truth.begin()) return 0;
  if (after == ground_truth.end()) return ground_truth.size() - 1;
  const auto before = after - 1;
  return (t - before->timestamp <= after->timestamp - t) ? before - ground_truth.begin()
                                                         : after - ground_truth.begin();
}

}  // namespace

std::vector<AssociatedPair> AssociateByTimestamp(const Trajectory& ground_truth,
                                                 const Trajectory& estimate, double max_dt_s) {
  if (!IsTimeSorted(ground_truth) || !IsTimeSorted(estimate)) {
    throw std::invalid_argument("AssociateByTimestamp: timestamps must not decrease");
  }
  std::vector<AssociatedPair> pairs;
  if (ground_truth.empty()) return pairs;
  double last_dt = 0;
  for (std::size_t est_index = 0; est_index < estimate.size(); ++est_index) {
    const double t = estimate[est_index].timestamp;
    const std::size_t gt_index = NearestIndex(ground_truth, t);
    const double dt = std::abs(ground_truth[gt_index].timestamp - t);
    if (!(dt <= max_dt_s)) continue;
    // Estimates arrive in time order, so a shared ground-truth pose is always the last one taken.
    if (!pairs.empty() && pairs.back().gt_index == gt_index) {
      if (dt < last_dt) {
        pairs.back().est_index = est_index;
        last_dt = dt;
      }
      continue;
    }
    pairs.push_back({gt_index, est_index});
    last_dt = dt;
  }
  return pairs;
}

}  // namespace pipescope
