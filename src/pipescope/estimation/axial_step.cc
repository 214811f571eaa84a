#include "pipescope/estimation/axial_step.h"

#include <cmath>

namespace pipescope {

double EstimateAxialStep(const std::vector<AxialStepObservation>& observations,
                         const AxialStepOptions& options, int* inliers) {
  std::vector<double> weights(observations.size(), 1.0);
  double delta_h = 0.0;
  const int rounds = options.huber_m > 0.0 ? std::max(1, options.iterations) : 1;
  for (int round = 0; round < rounds; ++round) {
    double numerator = 0.0, denominator = 0.0;
    for (std::size_t i = 0; i < observations.size(); ++i) {
      const AxialStepObservation& o = observations[i];
      if (!(o.track.n > 0.0)) continue;
      const SurfacePoint mean = o.track.Mean();
      numerator += weights[i] * o.track.n * (mean.h - o.predicted.h);
      denominator += weights[i] * o.track.n;
    }
    if (!(denominator > 0.0)) return 0.0;
    delta_h = numerator / denominator;
    if (!(options.huber_m > 0.0)) break;
    for (std::size_t i = 0; i < observations.size(); ++i) {
      const AxialStepObservation& o = observations[i];
      if (!(o.track.n > 0.0)) continue;
      const SurfacePoint mean = o.track.Mean();
      const double d = std::hypot(o.predicted.h + delta_h - mean.h, o.predicted.rho - mean.rho);
      weights[i] = d <= options.huber_m ? 1.0 : options.huber_m / d;
    }
  }
  if (inliers != nullptr) {
    *inliers = 0;
    for (const AxialStepObservation& o : observations) {
      if (!(o.track.n > 0.0)) continue;
      const SurfacePoint mean = o.track.Mean();
      const double d = std::hypot(o.predicted.h + delta_h - mean.h, o.predicted.rho - mean.rho);
      if (options.huber_m <= 0.0 || d <= options.huber_m) ++*inliers;
    }
  }
  return delta_h;
}

}  // namespace pipescope
