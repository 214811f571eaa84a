#pragma once

#include <opencv2/core.hpp>

namespace pipescope {

// Sign convention of every dense registration kernel in this folder: the shift t = (tx, ty) of
// `next` relative to `reference` is the translation that maps a reference pixel x to the pixel
// x + t of `next` that shows the same point, next(x + t) = reference(x) (000 eq. 12: x' = x + t).
// Content that moves right and down between the frames gives positive tx and ty.

// The error functions of 000 §4.1.2.
enum class FullSearchCost {
  kSad,   // eq. 13, sum of absolute differences
  kSsd,   // eq. 14, sum of squared differences
  kZncc,  // eq. 15-17, negated zero-normalised cross correlation (in [-1, 1], lower is better)
};

const char* FullSearchCostName(FullSearchCost cost);

struct FullSearchOptions {
  // 000 uses SAD for most of its results, as the cheapest of the three (§4.2.1); ZNCC is better
  // with blur and large displacements (§6.2.1).
  FullSearchCost cost = FullSearchCost::kSad;
  // The search window |tx| <= max_shift_x_px, |ty| <= max_shift_y_px (Algorithm 1's x_MAX,
  // y_MAX). 000 bounds it by the maximum speed and the frame rate, wider along the pipe axis
  // (image x, eq. 19) than across it; these defaults suit the quarter-resolution frames.
  // Values beyond the image are clamped to (width - 1, height - 1).
  int max_shift_x_px = 32;
  int max_shift_y_px = 16;
  // Shifts whose overlap is smaller than this fraction of the image are not considered (their
  // cost is +inf): costs normalised by a tiny overlap are noise. 000 registers pairs with about
  // 30 % overlap (Fig. 8).
  double min_overlap_fraction = 0.25;
  // Coarse-to-fine search (not in 000, which searches exhaustively at one resolution): with
  // L > 0 the whole window is searched on level L of a Gaussian pyramid, then each finer level
  // searches +-pyramid_search_radius_px around twice the coarser level's best shift. Mainly for
  // SAD, which has no FFT form; it can miss a minimum narrower than 2^L pixels.
  int pyramid_levels = 0;
  int pyramid_search_radius_px = 2;
};

struct FullSearchResult {
  cv::Point shift;  // the best integer shift t (see the sign convention above)
  double cost = 0;  // its cost: per overlap pixel for SAD and SSD, in [-1, 1] for ZNCC
  FullSearchCost metric = FullSearchCost::kSsd;  // the error function that scored the window
  // CV_64F, (2 max_shift_y_px + 1) rows by (2 max_shift_x_px + 1) columns (after clamping):
  // element (ty + max_shift_y_px, tx + max_shift_x_px) is the cost of shift (tx, ty), +inf where
  // the overlap is too small or, with pyramid_levels > 0, the shift was not evaluated.
  cv::Mat cost_surface;
  int max_shift_x_px = 0;  // the window actually searched (after clamping)
  int max_shift_y_px = 0;
};

// Full search for the integer translation between two images (000 Algorithm 1): every shift in
// the window is scored over the overlap of the two images and normalised by the overlap area,
//   SAD(t) = 1/N sum |R(x) - I(x + t)|,   SSD(t) = 1/N sum (R(x) - I(x + t))^2,
//   ZNCC(t) = -sum (R - mu_R)(I - mu_I) / sqrt(sum (R - mu_R)^2 sum (I - mu_I)^2),
// sums over the N reference pixels x whose x + t is inside `next`, with the means taken over the
// overlap (eq. 16-17). SSD and ZNCC come from one FFT cross-correlation and integral images of
// the intensities and their squares (O(P log P) for all shifts), SAD from a vectorised loop per
// shift. Ties go to the shift nearest zero, so a still pair gives exactly (0, 0).
// Images: one channel, the same size, any depth (converted to float; gain-corrected CV_32F
// frames of any range are expected). Throws InputError for a bad pair.
FullSearchResult RegisterFullSearch(const cv::Mat& reference, const cv::Mat& next,
                                    const FullSearchOptions& options = {});

// Where the cost surface's minimum lies relative to the best integer shift, per axis, from the
// best cost and its two neighbours on that axis: the vertex of the parabola through them for SSD
// and ZNCC, whose costs are quadratic about the minimum; for SAD, whose cost is V-shaped
// (|t - r| times the summed gradient, to first order), of the two lines of opposite slopes
// through them (equiangular fit; the parabola would halve small residuals). In [-0.5, 0.5], 0 on
// an axis where a neighbour is missing (window edge, not evaluated) or the best is not lower
// than both neighbours' mean.
// Not a registration: the full search stays integer (000 Algorithm 1); this says how much its
// rounding threw away, which the odometry uses to place key frames (pipeline/dense_vo.h).
cv::Point2d RoundingResidual(const FullSearchResult& result);

}  // namespace pipescope
