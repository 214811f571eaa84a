#pragma once

#include "pipescope/estimation/surface_point.h"

namespace pipescope {

// The running sufficient statistics S(g) of one world point (000 eq. 41): the count n and the
// sums of h, h^2, rho, rho^2 over the n surface estimates X(g)_j made so far, one per key frame
// that saw the point. Contributions can be removed again (000 §5.3.3).
struct TrackStatistics {
  double n = 0.0;
  double sum_h = 0.0;
  double sum_h2 = 0.0;
  double sum_rho = 0.0;
  double sum_rho2 = 0.0;

  void Add(const SurfacePoint& point);
  void Remove(const SurfacePoint& point);
  SurfacePoint Mean() const { return {sum_h / n, sum_rho / n}; }
  // Eq. 43-44: sum_j (h - h_j)^2 + (rho - rho_j)^2 from the sums alone. Equal to
  // n |(h, rho) - Mean()|^2 + the spread of the estimates, which the estimate cannot change, so
  // minimising eq. 42 is minimising the residuals sqrt(n) ((h, rho) - Mean()).
  double Error(const SurfacePoint& point) const;
};

}  // namespace pipescope
