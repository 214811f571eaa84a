#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

namespace pipescope {

// The outlier removal of 001 §III-C (used again for the T-intersections, §III-D): each
// observation's error u - u' is Huber-weighted (scaled by sqrt(w), w = min(1, huber / |e|)), and
// an observation whose weighted x or y lies more than mad_factor * 1.4826 * MAD from the median
// of all the weighted components is an outlier. The MAD has a floor, `min_mad_px`, so a
// near-perfect set keeps its observations. `errors`: unset for observations already removed.
// Returns, per observation, whether it is a new outlier.
std::vector<bool> MadOutliers(const std::vector<std::optional<Eigen::Vector2d>>& errors,
                              double huber_px, double mad_factor, double min_mad_px);

}  // namespace pipescope
