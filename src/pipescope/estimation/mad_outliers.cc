#include "pipescope/estimation/mad_outliers.h"

#include <algorithm>
#include <cmath>

#include "pipescope/util/median.h"

namespace pipescope {

std::vector<bool> MadOutliers(const std::vector<std::optional<Eigen::Vector2d>>& errors,
                              double huber_px, double mad_factor, double min_mad_px) {
  std::vector<bool> outlier(errors.size(), false);
  std::vector<double> weighted;
  std::vector<Eigen::Vector2d> per_observation(errors.size());
  for (std::size_t k = 0; k < errors.size(); ++k) {
    if (!errors[k]) continue;
    const double norm = errors[k]->norm();
    const double weight = norm <= huber_px ? 1.0 : huber_px / norm;
    per_observation[k] = std::sqrt(weight) * *errors[k];
    weighted.push_back(per_observation[k].x());
    weighted.push_back(per_observation[k].y());
  }
  if (weighted.empty()) return outlier;
  const double median = UpperMedian(weighted);
  std::vector<double> deviations;
  deviations.reserve(weighted.size());
  for (double value : weighted) deviations.push_back(std::abs(value - median));
  const double mad = std::max(min_mad_px, 1.4826 * UpperMedian(deviations));
  for (std::size_t k = 0; k < errors.size(); ++k) {
    if (!errors[k]) continue;
    outlier[k] = std::abs(per_observation[k].x() - median) > mad_factor * mad ||
                 std::abs(per_observation[k].y() - median) > mad_factor * mad;
  }
  return outlier;
}

}  // namespace pipescope
