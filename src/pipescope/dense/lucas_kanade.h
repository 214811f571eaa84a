#pragma once

#include <opencv2/core.hpp>

namespace pipescope {

// How the next image is sampled at the current sub-pixel shift. The shift is the same for every
// pixel, so either is a separable filter with fixed weights.
enum class ShiftInterpolation {
  kBilinear,  // 2x2 taps; cheaper, but smooths by an amount that depends on the fraction
  kBicubic,   // 4x4 taps, Catmull-Rom (Keys a = -0.5); less sub-pixel bias
};

struct LucasKanadeOptions {
  // Bergen et al.'s hierarchical framework (000 §4.2.2): Gauss-Newton from the coarsest level of
  // a Gaussian pyramid down to the full image. At most num_levels levels, the coarsest at least
  // min_level_size_px on its shorter side (160x120 gets 3 levels, 256x192 and 640x480 get 4).
  int num_levels = 4;
  int min_level_size_px = 24;
  // Stop a level when the update |dt| falls below the tolerance (in that level's pixels) or after
  // max_iterations. The full-resolution level uses convergence_px; the coarser levels only seed
  // the next one, so a looser tolerance there saves iterations without changing the result.
  int max_iterations = 50;
  double convergence_px = 1e-4;
  double coarse_convergence_px = 1e-2;
  // Also estimate a gain a and bias b, next(x + t) = a reference(x) + b (000 §4.1.2 and [3, 38]
  // discuss bias and gain; 000 itself corrects gain beforehand and leaves this off).
  bool estimate_gain_bias = false;
  ShiftInterpolation interpolation = ShiftInterpolation::kBicubic;
  // A level whose valid region (pixels whose shifted position is inside `next`) is smaller than
  // this fraction of the level is not used; if that happens at full resolution the result is
  // not converged.
  double min_overlap_fraction = 0.25;
  // Pixels within this distance (x, y) of either image's edges are not compared (full
  // resolution; scaled down with the pyramid). For images whose filtering treats the edges
  // differently from the interior, such as local contrast normalisation (local_contrast.h): near
  // an edge the filter's support is one-sided, a difference fixed in the frame that pulls the
  // shift across that edge towards zero.
  cv::Point2d border_px{0.0, 0.0};
};

struct LucasKanadeResult {
  cv::Point2d shift;  // t with next(x + t) = reference(x), sub-pixel (sign as in full_search.h)
  double gain = 1.0;  // a and b when estimate_gain_bias, else 1 and 0
  double bias = 0.0;
  double rms_residual = 0.0;  // RMS of next(x + t) - a reference(x) - b at full resolution
  int num_pixels = 0;         // pixels in the final residual
  int iterations = 0;         // Gauss-Newton iterations over all levels
  int final_level_iterations = 0;
  // The last update at full resolution was below convergence_px, with a well-conditioned
  // normal matrix and enough overlap.
  bool converged = false;
  // Covariance of the shift, sigma^2 (J^T J)^-1 with sigma^2 the residual variance (the
  // Gauss-Newton estimate; it ignores spatially correlated noise, so it is optimistic).
  cv::Matx22d covariance = cv::Matx22d::zeros();
};

// Hierarchical Gauss-Newton translational registration (Bergen et al., 000 eq. 20-27): minimises
//   E(t) = sum_x [next(x + t) - reference(x)]^2                                   (eq. 21)
// over the pixels x whose x + t falls inside `next` (the warped image's border is excluded, not
// extrapolated), by solving the normal equations (eq. 27)
//   (sum_x g g^T) dt = -sum_x g dI,   dI = next(x + t) - reference(x),            (eq. 22, 26)
// and t <- t + dt until |dt| < convergence_px. For the gradient g we use the mean of the
// reference's gradient and the warped next image's gradient (efficient second-order
// minimisation, Benhimane and Malis 2004): same minimum as eq. 22's gradient of the warped
// image, fewer iterations. `initial_shift` is in full-resolution pixels.
// Images: one channel, the same size, any depth (converted to float). Throws InputError for a
// bad pair.
LucasKanadeResult RegisterLucasKanade(const cv::Mat& reference, const cv::Mat& next,
                                      const LucasKanadeOptions& options = {},
                                      cv::Point2d initial_shift = {0.0, 0.0});

}  // namespace pipescope
