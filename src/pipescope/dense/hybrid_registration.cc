#include "pipescope/dense/hybrid_registration.h"

#include <cmath>

#include "pipescope/dense/dense_image.h"

namespace pipescope {
namespace {

// t^T C^-1 t, or +inf when C is not invertible.
double SquaredMahalanobis(cv::Point2d t, const cv::Matx22d& covariance) {
  const double det = cv::determinant(covariance);
  if (!(det > 0.0)) return HUGE_VAL;
  const cv::Vec2d v(t.x, t.y);
  return (v.t() * covariance.inv() * v)(0);
}

}  // namespace

HybridResult RegisterHybrid(const cv::Mat& reference, const cv::Mat& next,
                            const HybridOptions& options) {
  cv::Mat r, n;
  PrepareRegistrationPair(reference, next, "hybrid registration", &r, &n);
  const FullSearchResult coarse = RegisterFullSearch(r, n, options.full_search);
  HybridResult result;
  result.integer_shift = coarse.shift;
  result.full_search_cost = coarse.cost;
  result.shift = cv::Point2d(coarse.shift);

  const LucasKanadeResult fine =
      RegisterLucasKanade(r, n, options.refinement, cv::Point2d(coarse.shift));
  result.iterations = fine.iterations;
  const cv::Point2d correction = fine.shift - cv::Point2d(coarse.shift);
  if (fine.converged && std::hypot(correction.x, correction.y) <= options.max_refinement_px) {
    result.shift = fine.shift;
    result.rms_residual = fine.rms_residual;
    result.refined = true;
  }

  if (coarse.shift == cv::Point(0, 0)) {
    const double norm = std::hypot(result.shift.x, result.shift.y);
    if (!result.refined || norm < options.still_shift_px ||
        SquaredMahalanobis(result.shift, fine.covariance) < options.still_chi2) {
      result.shift = cv::Point2d(0.0, 0.0);
      result.still = true;
    }
  }
  return result;
}

}  // namespace pipescope
