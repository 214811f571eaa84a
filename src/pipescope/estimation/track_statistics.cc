#include "pipescope/estimation/track_statistics.h"

namespace pipescope {

void TrackStatistics::Add(const SurfacePoint& point) {
  n += 1.0;
  sum_h += point.h;
  sum_h2 += point.h * point.h;
  sum_rho += point.rho;
  sum_rho2 += point.rho * point.rho;
}

void TrackStatistics::Remove(const SurfacePoint& point) {
  n -= 1.0;
  sum_h -= point.h;
  sum_h2 -= point.h * point.h;
  sum_rho -= point.rho;
  sum_rho2 -= point.rho * point.rho;
  if (n <= 0.0) *this = TrackStatistics();
}

double TrackStatistics::Error(const SurfacePoint& point) const {
  return n * point.h * point.h - 2.0 * point.h * sum_h + sum_h2 + n * point.rho * point.rho -
         2.0 * point.rho * sum_rho + sum_rho2;
}

}  // namespace pipescope
