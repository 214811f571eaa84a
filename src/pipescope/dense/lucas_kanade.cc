#include "pipescope/dense/lucas_kanade.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "pipescope/dense/dense_image.h"

namespace pipescope {
namespace {

// Interpolation weights of the taps at offsets first_tap, first_tap + 1, ... for a sample at
// fraction f in [0, 1) past the integer position.
struct ShiftKernel {
  int first_tap = 0;
  int num_taps = 2;
  float weights[4] = {0, 0, 0, 0};
};

// Keys' cubic convolution kernel with a = -0.5 (Catmull-Rom).
double Cubic(double s) {
  constexpr double a = -0.5;
  s = std::abs(s);
  if (s <= 1.0) return ((a + 2.0) * s - (a + 3.0)) * s * s + 1.0;
  if (s < 2.0) return ((a * s - 5.0 * a) * s + 8.0 * a) * s - 4.0 * a;
  return 0.0;
}

ShiftKernel MakeKernel(ShiftInterpolation interpolation, double fraction) {
  ShiftKernel kernel;
  if (interpolation == ShiftInterpolation::kBilinear) {
    kernel.first_tap = 0;
    kernel.num_taps = 2;
    kernel.weights[0] = static_cast<float>(1.0 - fraction);
    kernel.weights[1] = static_cast<float>(fraction);
  } else {
    kernel.first_tap = -1;
    kernel.num_taps = 4;
    for (int k = 0; k < 4; ++k) kernel.weights[k] = static_cast<float>(Cubic(fraction - (k - 1)));
  }
  return kernel;
}

// The range [begin, end) of output coordinates x whose taps x + integer + first_tap ...
// x + integer + first_tap + num_taps - 1 all lie in [0, length).
void ValidRange(int length, int integer, const ShiftKernel& kernel, int* begin, int* end) {
  *begin = std::max(0, -(integer + kernel.first_tap));
  *end = std::min(length, length - (integer + kernel.first_tap + kernel.num_taps - 1));
}

// next shifted by a constant sub-pixel t: warped(x) = next(x + t) on the rectangle `valid` of
// output pixels whose taps are all inside `next` (warped is valid.size(), pixel (0, 0) is
// valid's corner). Separable: rows first, then columns, each with fixed weights.
cv::Mat ShiftImage(const cv::Mat& next, cv::Point2d t, ShiftInterpolation interpolation,
                   cv::Rect* valid) {
  const int ix = static_cast<int>(std::floor(t.x));
  const int iy = static_cast<int>(std::floor(t.y));
  const ShiftKernel kx = MakeKernel(interpolation, t.x - ix);
  const ShiftKernel ky = MakeKernel(interpolation, t.y - iy);
  int x0, x1, y0, y1;
  ValidRange(next.cols, ix, kx, &x0, &x1);
  ValidRange(next.rows, iy, ky, &y0, &y1);
  if (x1 <= x0 || y1 <= y0) {
    *valid = cv::Rect();
    return cv::Mat();
  }
  *valid = cv::Rect(x0, y0, x1 - x0, y1 - y0);
  const int width = x1 - x0;
  // Horizontal pass over the source rows the vertical taps need.
  const int row0 = y0 + iy + ky.first_tap;
  const int num_rows = (y1 - y0) + ky.num_taps - 1;
  cv::Mat horizontal(num_rows, width, CV_32F);
  for (int j = 0; j < num_rows; ++j) {
    const float* src = next.ptr<float>(row0 + j) + x0 + ix + kx.first_tap;
    float* dst = horizontal.ptr<float>(j);
    if (kx.num_taps == 2) {
      const float w0 = kx.weights[0], w1 = kx.weights[1];
      for (int x = 0; x < width; ++x) dst[x] = w0 * src[x] + w1 * src[x + 1];
    } else {
      const float w0 = kx.weights[0], w1 = kx.weights[1], w2 = kx.weights[2], w3 = kx.weights[3];
      for (int x = 0; x < width; ++x) {
        dst[x] = w0 * src[x] + w1 * src[x + 1] + w2 * src[x + 2] + w3 * src[x + 3];
      }
    }
  }
  cv::Mat warped(y1 - y0, width, CV_32F);
  for (int y = 0; y < warped.rows; ++y) {
    float* dst = warped.ptr<float>(y);
    if (ky.num_taps == 2) {
      const float* a = horizontal.ptr<float>(y);
      const float* b = horizontal.ptr<float>(y + 1);
      const float w0 = ky.weights[0], w1 = ky.weights[1];
      for (int x = 0; x < width; ++x) dst[x] = w0 * a[x] + w1 * b[x];
    } else {
      const float* a = horizontal.ptr<float>(y);
      const float* b = horizontal.ptr<float>(y + 1);
      const float* c = horizontal.ptr<float>(y + 2);
      const float* d = horizontal.ptr<float>(y + 3);
      const float w0 = ky.weights[0], w1 = ky.weights[1], w2 = ky.weights[2], w3 = ky.weights[3];
      for (int x = 0; x < width; ++x) dst[x] = w0 * a[x] + w1 * b[x] + w2 * c[x] + w3 * d[x];
    }
  }
  return warped;
}

// Central-difference gradients (half the difference of the two neighbours); the one-pixel
// border is left at zero and never used.
void CentralGradients(const cv::Mat& image, cv::Mat* gx, cv::Mat* gy) {
  *gx = cv::Mat::zeros(image.size(), CV_32F);
  *gy = cv::Mat::zeros(image.size(), CV_32F);
  for (int y = 1; y + 1 < image.rows; ++y) {
    const float* above = image.ptr<float>(y - 1);
    const float* row = image.ptr<float>(y);
    const float* below = image.ptr<float>(y + 1);
    float* dx = gx->ptr<float>(y);
    float* dy = gy->ptr<float>(y);
    for (int x = 1; x + 1 < image.cols; ++x) {
      dx[x] = 0.5f * (row[x + 1] - row[x - 1]);
      dy[x] = 0.5f * (below[x] - above[x]);
    }
  }
}

// The Gauss-Newton system of one iteration: J^T J and J^T r for the parameters
// (tx, ty[, gain, bias]), the residual sum of squares and the pixel count.
struct NormalEquations {
  cv::Matx44d jtj = cv::Matx44d::zeros();
  cv::Vec4d jtr = cv::Vec4d::all(0.0);
  double residual_sum_squares = 0;
  int num_pixels = 0;
};

// One linearisation at shift t with photometric parameters (gain, bias): residual
// r = next(x + t) - gain reference(x) - bias, Jacobian [g_x, g_y, -reference, -1] with
// g = (grad next(x + t) + gain grad reference(x)) / 2. Returns false when the valid region is
// smaller than min_pixels.
bool Linearise(const cv::Mat& reference, const cv::Mat& ref_gx, const cv::Mat& ref_gy,
               const cv::Mat& next, cv::Point2d t, double gain, double bias,
               bool estimate_gain_bias, ShiftInterpolation interpolation, int min_pixels,
               const cv::Rect& domain, NormalEquations* equations) {
  *equations = NormalEquations();
  cv::Rect valid;
  const cv::Mat warped = ShiftImage(next, t, interpolation, &valid);
  // Pixels of `domain` with both neighbours of the warped image and of the reference available.
  const int x0 = std::max({valid.x + 1, 1, domain.x});
  const int x1 = std::min({valid.x + valid.width - 1, reference.cols - 1, domain.x + domain.width});
  const int y0 = std::max({valid.y + 1, 1, domain.y});
  const int y1 =
      std::min({valid.y + valid.height - 1, reference.rows - 1, domain.y + domain.height});
  if (x1 <= x0 || y1 <= y0 || (x1 - x0) * (y1 - y0) < min_pixels) return false;

  const float g = static_cast<float>(gain);
  const float b = static_cast<float>(bias);
  double h00 = 0, h01 = 0, h11 = 0, e0 = 0, e1 = 0, rss = 0;
  double h02 = 0, h03 = 0, h12 = 0, h13 = 0, h22 = 0, h23 = 0, e2 = 0, e3 = 0, sum_one = 0;
  for (int y = y0; y < y1; ++y) {
    const float* w_above = warped.ptr<float>(y - valid.y - 1);
    const float* w_row = warped.ptr<float>(y - valid.y);
    const float* w_below = warped.ptr<float>(y - valid.y + 1);
    const float* r_row = reference.ptr<float>(y);
    const float* rx_row = ref_gx.ptr<float>(y);
    const float* ry_row = ref_gy.ptr<float>(y);
    // Row sums in float (vectorisable), added in double once per row.
    float s00 = 0, s01 = 0, s11 = 0, s0 = 0, s1 = 0, srr = 0;
    float s02 = 0, s03 = 0, s12 = 0, s13 = 0, s22 = 0, s23 = 0, s2 = 0, s3 = 0;
    for (int x = x0; x < x1; ++x) {
      const int wx = x - valid.x;
      const float ref = r_row[x];
      const float r = w_row[wx] - g * ref - b;
      const float gx = 0.25f * (w_row[wx + 1] - w_row[wx - 1]) + 0.5f * g * rx_row[x];
      const float gy = 0.25f * (w_below[wx] - w_above[wx]) + 0.5f * g * ry_row[x];
      s00 += gx * gx;
      s01 += gx * gy;
      s11 += gy * gy;
      s0 += gx * r;
      s1 += gy * r;
      srr += r * r;
      if (estimate_gain_bias) {
        s02 -= gx * ref;
        s03 -= gx;
        s12 -= gy * ref;
        s13 -= gy;
        s22 += ref * ref;
        s23 += ref;
        s2 -= ref * r;
        s3 -= r;
      }
    }
    h00 += s00, h01 += s01, h11 += s11, e0 += s0, e1 += s1, rss += srr;
    h02 += s02, h03 += s03, h12 += s12, h13 += s13, h22 += s22, h23 += s23, e2 += s2, e3 += s3;
  }
  const int n = (x1 - x0) * (y1 - y0);
  sum_one = n;
  equations->num_pixels = n;
  equations->residual_sum_squares = rss;
  equations->jtj = cv::Matx44d(h00, h01, h02, h03,  //
                               h01, h11, h12, h13,  //
                               h02, h12, h22, h23,  //
                               h03, h13, h23, sum_one);
  equations->jtr = cv::Vec4d(e0, e1, e2, e3);
  return true;
}

// The reference pixels at least `border` from its edges whose warped value and its two
// neighbours can be sampled, `border` from the next image's edges, for every shift within
// `margin` of `center` (either interpolation: taps -1 ... +2). Gauss-Newton keeps this set while
// the shift stays within the margin: a set that followed floor(t) would change at each integer
// crossing, and a shift that settles next to one could cycle between two sets.
cv::Rect StableDomain(cv::Size size, cv::Point2d center, double margin, cv::Point2d border) {
  const auto begin = [&](double c, double b) {
    return std::max(static_cast<int>(std::ceil(1.0 + b)),
                    static_cast<int>(std::ceil(3.0 + b - (c - margin))));
  };
  const auto end = [&](double c, double b, int length) {
    return std::min(static_cast<int>(std::floor(length - 1.0 - b)),
                    static_cast<int>(std::floor(length - 4.0 - b - (c + margin))) + 1);
  };
  const int x0 = begin(center.x, border.x), y0 = begin(center.y, border.y);
  const int x1 = end(center.x, border.x, size.width), y1 = end(center.y, border.y, size.height);
  if (x1 <= x0 || y1 <= y0) return cv::Rect();
  return cv::Rect(x0, y0, x1 - x0, y1 - y0);
}

// Solves J^T J d = -J^T r for the active parameters (2 or 4). False when the system is not
// positive definite (no texture, or texture in one direction only).
bool SolveStep(const NormalEquations& eq, bool estimate_gain_bias, cv::Vec4d* step,
               cv::Matx22d* shift_block_inverse) {
  *step = cv::Vec4d::all(0.0);
  if (!estimate_gain_bias) {
    const cv::Matx22d h(eq.jtj(0, 0), eq.jtj(0, 1), eq.jtj(1, 0), eq.jtj(1, 1));
    const double det = h(0, 0) * h(1, 1) - h(0, 1) * h(1, 0);
    const double trace = h(0, 0) + h(1, 1);
    // Reject a (near-)singular matrix: the smaller eigenvalue below 1e-9 of the larger one.
    if (!(trace > 0.0) || det <= 1e-9 * trace * trace) return false;
    *shift_block_inverse = h.inv();
    const cv::Vec2d d = *shift_block_inverse * cv::Vec2d(-eq.jtr[0], -eq.jtr[1]);
    (*step)[0] = d[0];
    (*step)[1] = d[1];
    return std::isfinite(d[0]) && std::isfinite(d[1]);
  }
  cv::Matx44d inverse;
  if (cv::invert(eq.jtj, inverse, cv::DECOMP_CHOLESKY) == 0.0) return false;
  *step = inverse * (-eq.jtr);
  *shift_block_inverse = cv::Matx22d(inverse(0, 0), inverse(0, 1), inverse(1, 0), inverse(1, 1));
  for (int k = 0; k < 4; ++k) {
    if (!std::isfinite((*step)[k])) return false;
  }
  return true;
}

}  // namespace

LucasKanadeResult RegisterLucasKanade(const cv::Mat& reference, const cv::Mat& next,
                                      const LucasKanadeOptions& options,
                                      cv::Point2d initial_shift) {
  cv::Mat r, n;
  PrepareRegistrationPair(reference, next, "Lucas-Kanade registration", &r, &n);
  const int levels =
      NumPyramidLevels(r.size(), std::max(1, options.num_levels), options.min_level_size_px);
  const std::vector<cv::Mat> r_pyramid = BuildGaussianPyramid(r, levels);
  const std::vector<cv::Mat> n_pyramid = BuildGaussianPyramid(n, levels);

  LucasKanadeResult result;
  cv::Point2d t = initial_shift;
  double gain = 1.0, bias = 0.0;
  for (int level = levels - 1; level >= 0; --level) {
    const cv::Mat& r_level = r_pyramid[level];
    const cv::Mat& n_level = n_pyramid[level];
    const double scale = 1.0 / (1 << level);
    const double tolerance = level == 0 ? options.convergence_px : options.coarse_convergence_px;
    const int min_pixels =
        static_cast<int>(std::ceil(options.min_overlap_fraction * r_level.rows * r_level.cols));
    cv::Mat gx, gy;
    CentralGradients(r_level, &gx, &gy);

    cv::Point2d t_level = t * scale;
    bool converged = false;
    int iterations = 0;
    NormalEquations equations;
    cv::Matx22d shift_block_inverse = cv::Matx22d::zeros();
    constexpr double kDomainMarginPx = 2.0;
    cv::Point2d domain_center = t_level;
    const cv::Point2d border = options.border_px * scale;
    cv::Rect domain = StableDomain(r_level.size(), domain_center, kDomainMarginPx, border);
    for (; iterations < options.max_iterations; ++iterations) {
      if (std::abs(t_level.x - domain_center.x) > kDomainMarginPx ||
          std::abs(t_level.y - domain_center.y) > kDomainMarginPx) {
        domain_center = t_level;
        domain = StableDomain(r_level.size(), domain_center, kDomainMarginPx, border);
      }
      if (!Linearise(r_level, gx, gy, n_level, t_level, gain, bias, options.estimate_gain_bias,
                     options.interpolation, std::max(min_pixels, 8), domain, &equations)) {
        break;
      }
      cv::Vec4d step;
      if (!SolveStep(equations, options.estimate_gain_bias, &step, &shift_block_inverse)) break;
      t_level += cv::Point2d(step[0], step[1]);
      gain += step[2];
      bias += step[3];
      if (std::hypot(step[0], step[1]) < tolerance) {
        converged = true;
        ++iterations;
        break;
      }
    }
    result.iterations += iterations;
    t = t_level / scale;
    if (level == 0) {
      result.final_level_iterations = iterations;
      result.converged = converged;
      result.num_pixels = equations.num_pixels;
      if (equations.num_pixels > 0) {
        const int dof = options.estimate_gain_bias ? 4 : 2;
        result.rms_residual = std::sqrt(equations.residual_sum_squares / equations.num_pixels);
        const double variance =
            equations.residual_sum_squares / std::max(1, equations.num_pixels - dof);
        result.covariance = variance * shift_block_inverse;
      }
    }
  }
  result.shift = t;
  result.gain = gain;
  result.bias = bias;
  return result;
}

}  // namespace pipescope
