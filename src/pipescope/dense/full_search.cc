#include "pipescope/dense/full_search.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "pipescope/dense/dense_image.h"

namespace pipescope {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// The shifts tx in [x0, x1], ty in [y0, y1] (inclusive) of one evaluation.
struct ShiftWindow {
  int x0, x1, y0, y1;
  int Width() const { return x1 - x0 + 1; }
  int Height() const { return y1 - y0 + 1; }
};

// The overlap of a shift: reference pixels [x0, x1) x [y0, y1) land on next pixels + t.
struct Overlap {
  int x0, x1, y0, y1;
  int Area() const { return std::max(0, x1 - x0) * std::max(0, y1 - y0); }
};

Overlap OverlapOf(int tx, int ty, cv::Size size) {
  return {std::max(0, -tx), std::min(size.width, size.width - tx), std::max(0, -ty),
          std::min(size.height, size.height - ty)};
}

// Sum of |a - b| over a rows x cols block of two images (row strides in floats). Sixteen
// independent float lanes per row let the compiler vectorise without reassociating one sum (a row
// is at most a few thousand pixels, so float lanes keep ~1e-6 relative precision); rows are
// summed in double. GCC builds an AVX2 clone, chosen at load time on CPUs that have it.
#if defined(__GNUC__) && defined(__x86_64__) && !defined(__clang__)
#define PIPESCOPE_AVX2_CLONE __attribute__((target_clones("avx2", "default")))
#else
#define PIPESCOPE_AVX2_CLONE
#endif
PIPESCOPE_AVX2_CLONE double BlockAbsoluteDifference(const float* a, std::size_t a_stride,
                                                    const float* b, std::size_t b_stride, int rows,
                                                    int cols) {
  constexpr int kLanes = 16;
  double total = 0;
  for (int y = 0; y < rows; ++y, a += a_stride, b += b_stride) {
    float lanes[kLanes] = {};
    int i = 0;
    for (; i + kLanes <= cols; i += kLanes) {
      for (int k = 0; k < kLanes; ++k) lanes[k] += std::fabs(a[i + k] - b[i + k]);
    }
    float sum = 0;
    for (int k = 0; k < kLanes; ++k) sum += lanes[k];
    for (; i < cols; ++i) sum += std::fabs(a[i] - b[i]);
    total += sum;
  }
  return total;
}

// SAD (eq. 13) per overlap pixel for every shift of the window: no FFT form, so one pass over
// the overlap per shift, row by row over contiguous memory.
cv::Mat SadWindow(const cv::Mat& reference, const cv::Mat& next, const ShiftWindow& window,
                  double min_overlap_px) {
  cv::Mat costs(window.Height(), window.Width(), CV_64F, cv::Scalar(kInfinity));
  for (int ty = window.y0; ty <= window.y1; ++ty) {
    for (int tx = window.x0; tx <= window.x1; ++tx) {
      const Overlap overlap = OverlapOf(tx, ty, reference.size());
      const int area = overlap.Area();
      if (area == 0 || area < min_overlap_px) continue;
      const double sum =
          BlockAbsoluteDifference(reference.ptr<float>(overlap.y0) + overlap.x0, reference.step1(),
                                  next.ptr<float>(overlap.y0 + ty) + overlap.x0 + tx, next.step1(),
                                  overlap.y1 - overlap.y0, overlap.x1 - overlap.x0);
      costs.at<double>(ty - window.y0, tx - window.x0) = sum / area;
    }
  }
  return costs;
}

// Sum of an integral image over [x0, x1) x [y0, y1).
inline double RectSum(const cv::Mat& integral, const Overlap& r) {
  return integral.at<double>(r.y1, r.x1) - integral.at<double>(r.y0, r.x1) -
         integral.at<double>(r.y1, r.x0) + integral.at<double>(r.y0, r.x0);
}

// SSD (eq. 14) or ZNCC (eq. 15-17) for every shift of the window. With R the reference and I
// the next image, over the overlap A(t) (N pixels) and its image A(t) + t:
//   sum (R - I)^2 = S_RR + S_II - 2 C(t),   C(t) = sum_x R(x) I(x + t),
//   ZNCC = -(C - S_R S_I / N) / sqrt((S_RR - S_R^2 / N)(S_II - S_I^2 / N)),
// where S_R, S_RR, S_I, S_II are box sums read from integral images and C, for all shifts at
// once, is the cross-correlation IDFT(F(I) conj F(R)) of the zero-padded images (padding by the
// largest shift keeps it linear, not circular). A common offset (the reference mean) is removed
// first, which changes neither cost but limits cancellation; all sums are in double.
cv::Mat CorrelationWindow(const cv::Mat& reference, const cv::Mat& next, FullSearchCost cost,
                          const ShiftWindow& window, double min_overlap_px) {
  const cv::Size size = reference.size();
  const double offset = cv::mean(reference)[0];
  cv::Mat r, n;
  reference.convertTo(r, CV_64F, 1.0, -offset);
  next.convertTo(n, CV_64F, 1.0, -offset);

  const int lag_x = std::max(std::abs(window.x0), std::abs(window.x1));
  const int lag_y = std::max(std::abs(window.y0), std::abs(window.y1));
  const int padded_w = cv::getOptimalDFTSize(size.width + lag_x);
  const int padded_h = cv::getOptimalDFTSize(size.height + lag_y);
  cv::Mat r_padded = cv::Mat::zeros(padded_h, padded_w, CV_64F);
  cv::Mat n_padded = cv::Mat::zeros(padded_h, padded_w, CV_64F);
  r.copyTo(r_padded(cv::Rect(0, 0, size.width, size.height)));
  n.copyTo(n_padded(cv::Rect(0, 0, size.width, size.height)));
  cv::Mat r_spectrum, n_spectrum, product, correlation;
  cv::dft(r_padded, r_spectrum, 0, size.height);
  cv::dft(n_padded, n_spectrum, 0, size.height);
  cv::mulSpectrums(n_spectrum, r_spectrum, product, 0, /*conjB=*/true);
  cv::dft(product, correlation, cv::DFT_INVERSE | cv::DFT_SCALE | cv::DFT_REAL_OUTPUT);

  cv::Mat r_sum, r_square_sum, n_sum, n_square_sum;
  cv::integral(r, r_sum, r_square_sum, CV_64F, CV_64F);
  cv::integral(n, n_sum, n_square_sum, CV_64F, CV_64F);

  cv::Mat costs(window.Height(), window.Width(), CV_64F, cv::Scalar(kInfinity));
  for (int ty = window.y0; ty <= window.y1; ++ty) {
    for (int tx = window.x0; tx <= window.x1; ++tx) {
      const Overlap a = OverlapOf(tx, ty, size);
      const int area = a.Area();
      if (area == 0 || area < min_overlap_px) continue;
      const Overlap b{a.x0 + tx, a.x1 + tx, a.y0 + ty, a.y1 + ty};
      const double c =
          correlation.at<double>((ty + padded_h) % padded_h, (tx + padded_w) % padded_w);
      const double s_rr = RectSum(r_square_sum, a);
      const double s_nn = RectSum(n_square_sum, b);
      double value;
      if (cost == FullSearchCost::kSsd) {
        value = std::max(0.0, s_rr + s_nn - 2.0 * c) / area;
      } else {
        const double s_r = RectSum(r_sum, a);
        const double s_n = RectSum(n_sum, b);
        const double covariance = c - s_r * s_n / area;
        const double r_variance = s_rr - s_r * s_r / area;
        const double n_variance = s_nn - s_n * s_n / area;
        // A flat overlap correlates with nothing: cost 0, as for uncorrelated images.
        constexpr double kFlatVariancePerPixel = 1e-12;
        value = (r_variance <= kFlatVariancePerPixel * area ||
                 n_variance <= kFlatVariancePerPixel * area)
                    ? 0.0
                    : -covariance / std::sqrt(r_variance * n_variance);
      }
      costs.at<double>(ty - window.y0, tx - window.x0) = value;
    }
  }
  return costs;
}

cv::Mat CostWindow(const cv::Mat& reference, const cv::Mat& next, FullSearchCost cost,
                   const ShiftWindow& window, double min_overlap_fraction) {
  const double min_overlap_px =
      std::max(1.0, min_overlap_fraction * reference.rows * reference.cols);
  if (cost == FullSearchCost::kSad) return SadWindow(reference, next, window, min_overlap_px);
  return CorrelationWindow(reference, next, cost, window, min_overlap_px);
}

// The lowest cost of a window; ties go to the shift nearest zero.
cv::Point BestShift(const cv::Mat& costs, const ShiftWindow& window, double* best_cost) {
  cv::Point best(0, 0);
  *best_cost = kInfinity;
  int best_norm = std::numeric_limits<int>::max();
  for (int ty = window.y0; ty <= window.y1; ++ty) {
    for (int tx = window.x0; tx <= window.x1; ++tx) {
      const double value = costs.at<double>(ty - window.y0, tx - window.x0);
      const int norm = tx * tx + ty * ty;
      if (value < *best_cost || (value == *best_cost && norm < best_norm)) {
        *best_cost = value;
        best_norm = norm;
        best = cv::Point(tx, ty);
      }
    }
  }
  return best;
}

int CeilDiv(int value, int divisor) { return (value + divisor - 1) / divisor; }

}  // namespace

const char* FullSearchCostName(FullSearchCost cost) {
  switch (cost) {
    case FullSearchCost::kSad:
      return "sad";
    case FullSearchCost::kSsd:
      return "ssd";
    case FullSearchCost::kZncc:
      return "zncc";
  }
  return "unknown";
}

FullSearchResult RegisterFullSearch(const cv::Mat& reference, const cv::Mat& next,
                                    const FullSearchOptions& options) {
  cv::Mat r, n;
  PrepareRegistrationPair(reference, next, "full search", &r, &n);
  FullSearchResult result;
  result.metric = options.cost;
  result.max_shift_x_px = std::clamp(options.max_shift_x_px, 0, r.cols - 1);
  result.max_shift_y_px = std::clamp(options.max_shift_y_px, 0, r.rows - 1);
  const ShiftWindow full{-result.max_shift_x_px, result.max_shift_x_px, -result.max_shift_y_px,
                         result.max_shift_y_px};
  result.cost_surface.create(full.Height(), full.Width(), CV_64F);
  result.cost_surface.setTo(kInfinity);

  const int levels = NumPyramidLevels(r.size(), 1 + std::max(0, options.pyramid_levels), 8);
  if (levels == 1) {
    result.cost_surface = CostWindow(r, n, options.cost, full, options.min_overlap_fraction);
    result.shift = BestShift(result.cost_surface, full, &result.cost);
    return result;
  }

  // Coarse to fine: the whole window on the coarsest level, then a small window around twice
  // the coarser estimate on each finer level, and one around zero, so that a false minimum of
  // the coarse level (whose images can be a few dozen pixels across) cannot hide the shift the
  // caller expects; zero is the prediction when the caller centres the pair on it.
  const std::vector<cv::Mat> r_pyramid = BuildGaussianPyramid(r, levels);
  const std::vector<cv::Mat> n_pyramid = BuildGaussianPyramid(n, levels);
  const int radius = std::max(1, options.pyramid_search_radius_px);
  cv::Point shift(0, 0);
  for (int level = levels - 1; level >= 0; --level) {
    const cv::Mat& r_level = r_pyramid[level];
    const int max_x = std::min(CeilDiv(result.max_shift_x_px, 1 << level), r_level.cols - 1);
    const int max_y = std::min(CeilDiv(result.max_shift_y_px, 1 << level), r_level.rows - 1);
    std::vector<ShiftWindow> windows;
    if (level == levels - 1) {
      windows.push_back({-max_x, max_x, -max_y, max_y});
    } else {
      const auto around = [&](cv::Point centre) {
        return ShiftWindow{std::max(-max_x, centre.x - radius), std::min(max_x, centre.x + radius),
                           std::max(-max_y, centre.y - radius), std::min(max_y, centre.y + radius)};
      };
      windows.push_back(around(2 * shift));
      if (std::abs(2 * shift.x) > 2 * radius || std::abs(2 * shift.y) > 2 * radius) {
        windows.push_back(around({0, 0}));  // disjoint from the first
      }
    }
    double best_cost = kInfinity;
    cv::Point best(0, 0);
    for (const ShiftWindow& window : windows) {
      const cv::Mat costs =
          CostWindow(r_level, n_pyramid[level], options.cost, window, options.min_overlap_fraction);
      double cost;
      const cv::Point candidate = BestShift(costs, window, &cost);
      if (cost < best_cost || (cost == best_cost && candidate.dot(candidate) < best.dot(best))) {
        best_cost = cost;
        best = candidate;
      }
      if (level == 0) {
        costs.copyTo(result.cost_surface(cv::Rect(window.x0 + result.max_shift_x_px,
                                                  window.y0 + result.max_shift_y_px, window.Width(),
                                                  window.Height())));
      }
    }
    shift = best;
    if (level == 0) result.cost = best_cost;
  }
  result.shift = shift;
  return result;
}

cv::Point2d RoundingResidual(const FullSearchResult& result) {
  const cv::Mat& costs = result.cost_surface;
  const int column = result.shift.x + result.max_shift_x_px;
  const int row = result.shift.y + result.max_shift_y_px;
  if (costs.empty() || row < 0 || row >= costs.rows || column < 0 || column >= costs.cols) {
    return {0.0, 0.0};
  }
  // The minimum of the parabola, or the V, through (-1, before), (0, best), (1, after).
  const bool v_shaped = result.metric == FullSearchCost::kSad;
  const auto vertex = [v_shaped](double before, double best, double after) {
    const double curvature = before - 2.0 * best + after;
    if (!std::isfinite(before) || !std::isfinite(after) || !(curvature > 0.0)) return 0.0;
    // The V's steeper side is the one with the higher neighbour: its slope is that rise.
    const double scale = v_shaped ? std::max(before, after) - best : curvature;
    return std::clamp(0.5 * (before - after) / scale, -0.5, 0.5);
  };
  const double best = costs.at<double>(row, column);
  const auto at = [&](int r, int c) {
    return r < 0 || r >= costs.rows || c < 0 || c >= costs.cols
               ? std::numeric_limits<double>::infinity()
               : costs.at<double>(r, c);
  };
  return {vertex(at(row, column - 1), best, at(row, column + 1)),
          vertex(at(row - 1, column), best, at(row + 1, column))};
}

}  // namespace pipescope
