#pragma once

#include <algorithm>
#include <vector>

namespace pipescope {

// The median (the upper one for an even count) of `values`, 0 for none; takes a copy because
// nth_element reorders.
inline double Median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const auto middle = values.begin() + values.size() / 2;
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

}  // namespace pipescope
