#pragma once

#include <algorithm>
#include <vector>

namespace pipescope {

// The two medians the project uses, each by its own name. Both take a copy, because they reorder.

// The median: the middle value, the mean of the middle two for an even count; 0 for none. For
// few samples whose middle two differ (the constant-velocity prediction of three pairs).
inline double Median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

// The upper median: the middle value, the upper of the middle two for an even count; 0 for
// none. One value of the sample itself, found in linear time (robust scales, flows, speeds).
inline double UpperMedian(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const auto middle = values.begin() + values.size() / 2;
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

}  // namespace pipescope
