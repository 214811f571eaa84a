#pragma once

#include <opencv2/core.hpp>

#include "pipescope/dense/full_search.h"
#include "pipescope/dense/lucas_kanade.h"

namespace pipescope {

struct HybridOptions {
  // Step 1: full search for the integer shift (000 Algorithm 1).
  FullSearchOptions full_search;
  // Step 2: Gauss-Newton refinement "on the finest resolution pair of images without resorting to
  // image pyramids" (000 §4.2.3), hence one level by default.
  LucasKanadeOptions refinement = [] {
    LucasKanadeOptions options;
    options.num_levels = 1;
    return options;
  }();
  // The full search lands within a pixel of the minimum (§4.2.3); a refinement that moves
  // further than this from the integer shift, or does not converge, is discarded and the integer
  // shift is returned (refined = false).
  double max_refinement_px = 1.5;
  // Still pairs. Iterative refinement "will almost always estimate non-zero motion, even if the
  // camera does not move", and the errors random-walk into the odometry (§4.2.3). A pair is
  // reported as still, with a shift of exactly (0, 0), when the full search finds (0, 0) and the
  // refined shift t is not distinguishable from zero: |t| < still_shift_px, or its squared
  // Mahalanobis distance t^T C^-1 t under the Gauss-Newton covariance C is below still_chi2
  // (chi-square with 2 degrees of freedom: 13.8 leaves 0.1 % of still pairs with false motion
  // under white noise). still_shift_px = 0.02 px is below what a quarter-resolution frame pair
  // can resolve; motion slower than that per frame is lost, which is the price of no drift.
  double still_shift_px = 0.02;
  double still_chi2 = 13.8;
};

struct HybridResult {
  cv::Point2d shift;            // final shift (sign as in full_search.h); exactly 0 when still
  cv::Point integer_shift;      // the full search's shift
  double full_search_cost = 0;  // its cost
  double rms_residual = 0;      // the refinement's residual (0 when not refined)
  int iterations = 0;           // refinement iterations
  bool refined = false;         // the refinement converged and was accepted
  bool still = false;           // reported as no motion (see HybridOptions)
};

// Full search followed by iterative refinement at full resolution (000 §4.2.3): the full search
// guarantees the global minimum within the window, Gauss-Newton adds sub-pixel precision.
// Images: one channel, the same size, any depth. Throws InputError for a bad pair.
HybridResult RegisterHybrid(const cv::Mat& reference, const cv::Mat& next,
                            const HybridOptions& options = {});

}  // namespace pipescope
