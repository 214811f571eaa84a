#include "pipescope/estimation/pass_consensus.h"

#include <cmath>
#include <stdexcept>

namespace pipescope {

std::vector<int> ConsistentLoopEdges(const std::vector<double>& earlier_path_m,
                                     const std::vector<double>& later_path_m,
                                     const PassConsensusOptions& options) {
  if (earlier_path_m.size() != later_path_m.size()) {
    throw std::invalid_argument("ConsistentLoopEdges: sizes differ");
  }
  const int n = static_cast<int>(earlier_path_m.size());
  if (n == 1) return {0};
  std::vector<int> best;
  double best_residual = 0.0;
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      const double later_step = later_path_m[i] - later_path_m[j];
      if (std::abs(later_step) < options.min_later_separation_m) continue;
      const double slope = (earlier_path_m[i] - earlier_path_m[j]) / later_step;
      // The passes drive the same way, and neither lost its scale by more than the ratio.
      if (!(slope >= 1.0 / options.max_scale_ratio && slope <= options.max_scale_ratio)) continue;
      const double offset = earlier_path_m[i] - slope * later_path_m[i];
      std::vector<int> agreeing;
      double residual = 0.0;
      for (int k = 0; k < n; ++k) {
        const double off = std::abs(earlier_path_m[k] - (offset + slope * later_path_m[k]));
        if (off > options.tolerance_m) continue;
        agreeing.push_back(k);
        residual += off;
      }
      if (agreeing.size() > best.size() ||
          (agreeing.size() == best.size() && residual < best_residual)) {
        best = agreeing;
        best_residual = residual;
      }
    }
  }
  return best;
}

}  // namespace pipescope
