#include "pipescope/dense/phase_correlation.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <vector>

#include "pipescope/dense/dense_image.h"

namespace pipescope {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

// Signed value of a circular index: 0 ... n/2 stay, the rest wrap to negative.
int Signed(int index, int n) { return index > n / 2 ? index - n : index; }

double At(const cv::Mat& surface, int x, int y) {
  const int w = surface.cols, h = surface.rows;
  return surface.at<float>(((y % h) + h) % h, ((x % w) + w) % w);
}

// One-dimensional parabola through (-1, a), (0, b), (1, c): vertex offset in [-0.5, 0.5] and
// vertex height.
void ParabolaVertex(double a, double b, double c, double* offset, double* height) {
  const double curvature = a - 2.0 * b + c;
  *offset = curvature < 0.0 ? std::clamp(0.5 * (a - c) / curvature, -0.5, 0.5) : 0.0;
  *height = b - 0.25 * (a - c) * *offset;
}

// Gaussian spectral weights, exp(-|f|^2 / (2 sigma^2)) with f in cycles per pixel: separable, a
// factor per column (x) and per row (y), scaled so that their mean over the bins is 1 and a
// perfect match still peaks at 1.
struct SpectralWeights {
  std::vector<float> x, y;

  SpectralWeights() = default;
  SpectralWeights(cv::Size padded, double sigma) {
    auto axis = [sigma](int n) {
      std::vector<float> w(n);
      double sum = 0;
      for (int k = 0; k < n; ++k) {
        const double f = static_cast<double>(Signed(k, n)) / n;
        sum += std::exp(-f * f / (2.0 * sigma * sigma));
      }
      for (int k = 0; k < n; ++k) {
        const double f = static_cast<double>(Signed(k, n)) / n;
        w[k] = static_cast<float>(n * std::exp(-f * f / (2.0 * sigma * sigma)) / sum);
      }
      return w;
    };
    x = axis(padded.width);
    y = axis(padded.height);
  }
  bool empty() const { return x.empty(); }
};

// Q = F{next} conj(F{reference}) / |...| (eq. 5 with our sign), times the spectral weights when
// there are any; bins of zero magnitude are set to 0.
cv::Mat CrossPowerSpectrum(const cv::Mat& next_spectrum, const cv::Mat& reference_spectrum,
                           const SpectralWeights& weights) {
  cv::Mat product;
  cv::mulSpectrums(next_spectrum, reference_spectrum, product, 0, /*conjB=*/true);
  for (int y = 0; y < product.rows; ++y) {
    float* row = product.ptr<float>(y);
    const float wy = weights.empty() ? 1.f : weights.y[y];
    const float* wx = weights.empty() ? nullptr : weights.x.data();
    for (int x = 0; x < product.cols; ++x) {
      const float re = row[2 * x], im = row[2 * x + 1];
      const float magnitude_squared = re * re + im * im;
      const float scale =
          magnitude_squared > 1e-30f ? (wx ? wy * wx[x] : 1.f) / std::sqrt(magnitude_squared) : 0.f;
      row[2 * x] = re * scale;
      row[2 * x + 1] = im * scale;
    }
  }
  return product;
}

// The window, DFT size and spectral weights for images of one size.
struct Transformer {
  cv::Size size;            // image size
  cv::Size padded;          // DFT size
  cv::Mat window;           // CV_32F, or empty for no window
  SpectralWeights weights;  // empty for none

  Transformer(cv::Size image_size, const PhaseCorrelationOptions& options)
      : size(image_size),
        padded(cv::getOptimalDFTSize(size.width), cv::getOptimalDFTSize(size.height)) {
    if (options.hann_window) cv::createHanningWindow(window, size, CV_32F);
    if (options.spectrum_sigma > 0.0) weights = SpectralWeights(padded, options.spectrum_sigma);
  }

  // The complex spectrum (CV_32FC2, padded size) of `image` with its windowed mean removed,
  // windowed and zero-padded.
  cv::Mat Spectrum(const cv::Mat& image) const {
    cv::Mat prepared;
    if (window.empty()) {
      prepared = image - cv::mean(image)[0];
    } else {
      const double mean = image.dot(window) / cv::sum(window)[0];
      cv::multiply(image - mean, window, prepared);
    }
    cv::Mat padded_image = cv::Mat::zeros(padded, CV_32F);
    prepared.copyTo(padded_image(cv::Rect(cv::Point(0, 0), size)));
    cv::Mat spectrum;
    cv::dft(padded_image, spectrum, cv::DFT_COMPLEX_OUTPUT, size.height);
    return spectrum;
  }
};

// Value, gradient and Hessian of the band-limited interpolant c(t) of the correlation surface
// c = F^-1{Q} at the (sub-pixel) position t; at integer t it is the DFT's own value. Q of a real
// surface is Hermitian, so the half plane kx in [0, P/2] gives the real part of the whole sum
// with the columns 0 < kx < P/2 counted twice (their mirrors -kx are the conjugates).
struct InterpolantDerivatives {
  double value, dx, dy, dxx, dxy, dyy;
};

InterpolantDerivatives EvaluateInterpolant(const cv::Mat& q, cv::Point2d t) {
  const int pw = q.cols, ph = q.rows;
  const int kx_end = pw / 2 + 1;
  std::vector<std::complex<double>> ex(kx_end);
  std::vector<double> wx(kx_end);
  for (int kx = 0; kx < kx_end; ++kx) {
    wx[kx] = kTwoPi * kx / pw;
    const bool self_paired = kx == 0 || 2 * kx == pw;
    ex[kx] = std::polar(self_paired ? 1.0 : 2.0, wx[kx] * t.x);
  }
  std::complex<double> c(0), cx(0), cxx(0), cy(0), cyy(0), cxy(0);
  const std::complex<double> i(0.0, 1.0);
  for (int row = 0; row < ph; ++row) {
    const double wy = kTwoPi * Signed(row, ph) / ph;
    const cv::Vec2f* q_row = q.ptr<cv::Vec2f>(row);
    double a0r = 0, a0i = 0, a1r = 0, a1i = 0, a2r = 0, a2i = 0;
    for (int kx = 0; kx < kx_end; ++kx) {
      // q * ex, then weighted by 1, w and w^2 (the factors i and i^2 are applied below).
      const double qr = q_row[kx][0], qi = q_row[kx][1];
      const double pr = qr * ex[kx].real() - qi * ex[kx].imag();
      const double pi = qr * ex[kx].imag() + qi * ex[kx].real();
      a0r += pr;
      a0i += pi;
      a1r += wx[kx] * pr;
      a1i += wx[kx] * pi;
      a2r += wx[kx] * wx[kx] * pr;
      a2i += wx[kx] * wx[kx] * pi;
    }
    const std::complex<double> ey = std::polar(1.0, wy * t.y);
    const std::complex<double> a0(a0r, a0i), a1 = i * std::complex<double>(a1r, a1i);
    const std::complex<double> a2 = -std::complex<double>(a2r, a2i);
    c += ey * a0;
    cx += ey * a1;
    cxx += ey * a2;
    cy += ey * (i * wy) * a0;
    cyy += ey * (-wy * wy) * a0;
    cxy += ey * (i * wy) * a1;
  }
  const double m = static_cast<double>(pw) * ph;
  return {c.real() / m,   cx.real() / m,  cy.real() / m,
          cxx.real() / m, cxy.real() / m, cyy.real() / m};
}

// The peak of the correlation surface c (CV_32F, padded size) and its spectrum q.
struct Peak {
  cv::Point2d position;
  double height = 0;
};

Peak FindPeak(const cv::Mat& surface, const cv::Mat& q, PhasePeakMethod method) {
  cv::Point integer;
  double max_value;
  cv::minMaxLoc(surface, nullptr, &max_value, nullptr, &integer);
  const int px = integer.x, py = integer.y;
  Peak peak;
  peak.position = cv::Point2d(Signed(px, surface.cols), Signed(py, surface.rows));
  peak.height = max_value;
  if (method == PhasePeakMethod::kCentroid3x3) {
    double sum = 0, sx = 0, sy = 0;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const double v = std::max(0.0, At(surface, px + dx, py + dy));
        sum += v;
        sx += v * dx;
        sy += v * dy;
      }
    }
    if (sum > 0.0) peak.position += cv::Point2d(sx / sum, sy / sum);
    return peak;
  }
  double offset_x, offset_y, height_x, height_y;
  ParabolaVertex(At(surface, px - 1, py), max_value, At(surface, px + 1, py), &offset_x, &height_x);
  ParabolaVertex(At(surface, px, py - 1), max_value, At(surface, px, py + 1), &offset_y, &height_y);
  peak.position += cv::Point2d(offset_x, offset_y);
  peak.height = height_x + height_y - max_value;
  if (method == PhasePeakMethod::kParabolic) return peak;

  // Newton's method on the interpolant, each step at most half a pixel; kept only while the
  // Hessian is negative definite (we are on the peak's cap).
  // Stops when the step is below 1e-4 px; the height is that of the last evaluation, which
  // differs from the final position's by a negligible second-order amount.
  cv::Point2d t = peak.position;
  double height = peak.height;
  for (int iteration = 0; iteration < 10; ++iteration) {
    const InterpolantDerivatives d = EvaluateInterpolant(q, t);
    const double det = d.dxx * d.dyy - d.dxy * d.dxy;
    if (!(d.dxx < 0.0 && det > 0.0)) break;
    height = d.value;
    cv::Point2d step(-(d.dyy * d.dx - d.dxy * d.dy) / det, -(d.dxx * d.dy - d.dxy * d.dx) / det);
    const double norm = std::hypot(step.x, step.y);
    if (norm > 0.5) step *= 0.5 / norm;
    t += step;
    if (norm < 1e-4) break;
  }
  if (std::hypot(t.x - peak.position.x, t.y - peak.position.y) < 1.0) {
    peak.position = t;
    peak.height = height;
  }
  return peak;
}

// Phase correlation of a prepared reference spectrum against the next spectrum.
struct Correlation {
  cv::Mat q;        // the weighted normalised cross-power spectrum
  cv::Mat surface;  // its inverse transform
};

Correlation Correlate(const cv::Mat& next_spectrum, const cv::Mat& reference_spectrum,
                      const SpectralWeights& weights) {
  Correlation correlation;
  correlation.q = CrossPowerSpectrum(next_spectrum, reference_spectrum, weights);
  cv::dft(correlation.q, correlation.surface,
          cv::DFT_INVERSE | cv::DFT_SCALE | cv::DFT_REAL_OUTPUT);
  return correlation;
}

Peak FindPeak(const Correlation& correlation, PhasePeakMethod method) {
  return FindPeak(correlation.surface, correlation.q, method);
}

// The reference rotated by `angle` about the centre: rotated(R (x - c) + c) = reference(x).
cv::Mat RotateAboutCentre(const cv::Mat& image, double angle) {
  const double cx = 0.5 * (image.cols - 1), cy = 0.5 * (image.rows - 1);
  const double cos_a = std::cos(angle), sin_a = std::sin(angle);
  const cv::Matx23d forward(cos_a, -sin_a, cx - (cos_a * cx - sin_a * cy),  //
                            sin_a, cos_a, cy - (sin_a * cx + cos_a * cy));
  cv::Mat rotated;
  cv::warpAffine(image, rotated, forward, image.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT_101);
  return rotated;
}

// The correlation set-up for one image size, with the spectrum of `next` at that size, which
// every correlation at that size shares.
struct Level {
  Transformer transformer;
  cv::Mat next_spectrum;

  Level(const cv::Mat& next, const PhaseCorrelationOptions& options)
      : transformer(next.size(), options), next_spectrum(transformer.Spectrum(next)) {}
  Correlation With(const cv::Mat& reference) const {
    return Correlate(next_spectrum, transformer.Spectrum(reference), transformer.weights);
  }
};

// The translation between the (aligned, i.e. rotated) reference and `next`.
// With refine_on_overlap: the integer shift from a first correlation on the coarse pyramid level
// (or at full resolution when there is none), then a second correlation on the overlap of the two
// images at that shift, each image cut to the overlap and windowed there, so that the windows
// move with the content. A window fixed to the frame weights the content of the two images
// differently and pulls the peak towards zero shift, by about 0.2 % of the shift with a Hann
// window. Without it, or when the overlap is too small: one correlation of the whole images.
// `known_estimate`: the first pass's result when the caller has it already.
Peak EstimateTranslation(const cv::Mat& reference, const cv::Mat& next, int coarse_level,
                         const Level* coarse, std::optional<Level>* full,
                         const PhaseCorrelationOptions& options,
                         std::optional<cv::Point2d> known_estimate = std::nullopt) {
  auto whole_images = [&] {
    if (!full->has_value()) full->emplace(next, options);
    return FindPeak((*full)->With(reference), options.peak_method);
  };
  if (!options.refine_on_overlap) return whole_images();
  cv::Point2d estimate;
  if (known_estimate) {
    estimate = *known_estimate;
  } else if (coarse_level > 0) {
    const cv::Mat reference_coarse = BuildGaussianPyramid(reference, coarse_level + 1).back();
    estimate = FindPeak(coarse->With(reference_coarse), PhasePeakMethod::kParabolic).position *
               static_cast<double>(1 << coarse_level);
  } else {
    if (!full->has_value()) full->emplace(next, options);
    estimate = FindPeak((*full)->With(reference), PhasePeakMethod::kParabolic).position;
  }
  const cv::Point shift(static_cast<int>(std::lround(estimate.x)),
                        static_cast<int>(std::lround(estimate.y)));
  const cv::Rect overlap = OverlapAtShift(reference.size(), shift);
  // At zero shift the overlap is the whole image; with too little overlap a second pass is no
  // better than the first.
  if (shift == cv::Point(0, 0) || overlap.width < 16 || overlap.height < 16 ||
      overlap.area() < reference.size().area() / 4) {
    return whole_images();
  }
  const Level cropped(next(overlap + shift), options);
  Peak fine = FindPeak(cropped.With(reference(overlap)), options.peak_method);
  // The residual should be within a pixel; if not, the coarse estimate was wrong.
  if (std::hypot(fine.position.x, fine.position.y) > 1.0) return whole_images();
  fine.position += cv::Point2d(shift);
  return fine;
}

// The rotation left between the rotated reference and `next`, whose translation is about
// `shift` (whole pixels), and the translation that goes with it: the two halves of their
// overlap, split across its longer side, are registered on their own. A rotation by d about the
// image centre c and a translation t move content at w by about d J (w - c) + t,
// J = [0, -1; 1, 0], so the halves' shifts s_1, s_2 at their centres w_1, w_2 differ by
// d J (w_2 - w_1), and t = (s_1 + s_2) / 2 - d J ((w_1 + w_2) / 2 - c). Their translations are
// known to a few hundredths of a pixel, so this measures d far better than the peak height's
// fall-off with angle, which is flat at the top. Empty when the halves are too small to
// register or disagree by more than a pixel and a half from `shift`.
struct RigidResidual {
  double rotation_rad;
  cv::Point2d shift;
};

std::optional<RigidResidual> SplitOverlapResidual(const cv::Mat& reference, const cv::Mat& next,
                                                  cv::Point shift,
                                                  const PhaseCorrelationOptions& options) {
  const cv::Rect overlap = OverlapAtShift(reference.size(), shift);
  const bool split_x = overlap.width >= overlap.height;
  const cv::Size half_size = split_x ? cv::Size(overlap.width / 2, overlap.height)
                                     : cv::Size(overlap.width, overlap.height / 2);
  if (half_size.width < 16 || half_size.height < 16) return std::nullopt;
  const cv::Point step = split_x ? cv::Point(overlap.width - half_size.width, 0)
                                 : cv::Point(0, overlap.height - half_size.height);
  cv::Point2d local_shift[2], centre[2];
  for (int half = 0; half < 2; ++half) {
    const cv::Rect area(overlap.tl() + half * step, half_size);
    const Level level(next(area + shift), options);
    const Peak fine = FindPeak(level.With(reference(area)), options.peak_method);
    if (std::hypot(fine.position.x, fine.position.y) > 1.5) return std::nullopt;
    local_shift[half] = fine.position + cv::Point2d(shift);
    centre[half] = cv::Point2d(area.x + 0.5 * (area.width - 1), area.y + 0.5 * (area.height - 1));
  }
  auto perpendicular = [](cv::Point2d v) { return cv::Point2d(-v.y, v.x); };  // J v
  const cv::Point2d d = centre[1] - centre[0];
  RigidResidual residual;
  residual.rotation_rad = perpendicular(d).dot(local_shift[1] - local_shift[0]) / d.dot(d);
  const cv::Point2d image_centre(0.5 * (reference.cols - 1), 0.5 * (reference.rows - 1));
  const cv::Point2d middle = 0.5 * (centre[0] + centre[1]);
  residual.shift = 0.5 * (local_shift[0] + local_shift[1]) -
                   residual.rotation_rad * perpendicular(middle - image_centre);
  return residual;
}

// The coarse pyramid level of PhaseCorrelationOptions::coarse_level_min_size_px: by the longer
// side, so that a wide band (160x60) gets one too.
int CoarseLevel(cv::Size size, int min_longer_side_px) {
  constexpr int kMaxLevel = 2, kMinShorterSidePx = 16;
  int level = 0;
  int longer = std::max(size.width, size.height), shorter = std::min(size.width, size.height);
  while (level < kMaxLevel && longer / 2 >= min_longer_side_px &&
         shorter / 2 >= kMinShorterSidePx) {
    longer /= 2;
    shorter /= 2;
    ++level;
  }
  return level;
}

}  // namespace

PhaseCorrelationResult RegisterPhaseCorrelation(const cv::Mat& reference, const cv::Mat& next,
                                                const PhaseCorrelationOptions& options,
                                                double rotation_prior_rad) {
  cv::Mat r, n;
  PrepareRegistrationPair(reference, next, "phase correlation", &r, &n);
  const int coarse_level = CoarseLevel(r.size(), options.coarse_level_min_size_px);
  std::optional<Level> coarse;
  if (coarse_level > 0) coarse.emplace(BuildGaussianPyramid(n, coarse_level + 1).back(), options);
  std::optional<Level> full;

  PhaseCorrelationResult result;
  if (!options.estimate_rotation) {
    const Peak peak =
        EstimateTranslation(r, n, coarse_level, coarse ? &*coarse : nullptr, &full, options);
    result.shift = peak.position;
    result.peak = peak.height;
    return result;
  }

  // Rotation search (003 eq. 7), scored by the height of the (parabolic) peak: whole steps of the
  // range on the coarse level, where each correlation is cheap and the peak falls off more
  // gently with angle; then the split-overlap correction (or parabolic refinements at full
  // resolution) for the sub-step angle.
  const cv::Mat r_coarse = BuildGaussianPyramid(r, coarse_level + 1).back();
  if (coarse_level == 0) full.emplace(n, options);
  const Level& search_level = coarse_level > 0 ? *coarse : *full;
  const double step = std::max(1e-6, options.rotation_step_rad);
  const int steps = std::max(0, static_cast<int>(std::floor(options.max_rotation_rad / step)));
  // The peaks of the whole steps k * step, k in -steps ... steps, each computed once.
  std::vector<std::optional<Peak>> peaks(2 * steps + 1);
  auto peak_of_step = [&](int k) -> const Peak& {
    std::optional<Peak>& cached = peaks[k + steps];
    if (!cached) {
      cached = FindPeak(search_level.With(RotateAboutCentre(r_coarse, k * step)),
                        PhasePeakMethod::kParabolic);
    }
    return *cached;
  };
  auto score_of_step = [&](int k) { return peak_of_step(k).height; };
  int best = 0;  // the best step so far
  if (options.rotation_from_prior) {
    // Climb from the predicted angle to the nearest maximum: a few correlations instead of the
    // whole range, since a pair's rotation changes little from the last one's.
    best = static_cast<int>(
        std::lround(std::clamp(rotation_prior_rad / step, -1.0 * steps, 1.0 * steps)));
    for (;;) {
      const double here = score_of_step(best);
      const double left = best > -steps ? score_of_step(best - 1) : -1.0;
      const double right = best < steps ? score_of_step(best + 1) : -1.0;
      if (left > here && left >= right) {
        --best;
      } else if (right > here) {
        ++best;
      } else {
        break;
      }
    }
  }
  // The whole range when there is no prior, or the climb ended on a weak peak: a maximum of the
  // noise, or a prior far from this pair's rotation.
  if (!options.rotation_from_prior || score_of_step(best) < options.rotation_search_min_peak) {
    for (int k = -steps; k <= steps; ++k) {
      if (score_of_step(k) > score_of_step(best)) best = k;
    }
  }
  double angle = best * step;
  double offset, height;
  if (best > -steps && best < steps) {
    ParabolaVertex(score_of_step(best - 1), score_of_step(best), score_of_step(best + 1), &offset,
                   &height);
    angle += offset * step;
  }
  angle = std::clamp(angle, -steps * step, steps * step);
  // The best step's correlation already holds the integer shift (within a step of the angle).
  std::optional<cv::Point2d> coarse_shift;
  if (coarse_level > 0) {
    const cv::Point2d position = peak_of_step(best).position;
    coarse_shift.emplace(position.x * (1 << coarse_level), position.y * (1 << coarse_level));
  }
  cv::Mat rotated = RotateAboutCentre(r, angle);
  Peak peak = EstimateTranslation(rotated, n, coarse_level, coarse ? &*coarse : nullptr, &full,
                                  options, coarse_shift);
  for (int iteration = 0; iteration < options.split_rotation_iterations; ++iteration) {
    const cv::Point shift(static_cast<int>(std::lround(peak.position.x)),
                          static_cast<int>(std::lround(peak.position.y)));
    const std::optional<RigidResidual> residual = SplitOverlapResidual(rotated, n, shift, options);
    if (!residual || std::abs(residual->rotation_rad) > step) break;
    angle = std::clamp(angle + residual->rotation_rad, -steps * step, steps * step);
    rotated = RotateAboutCentre(r, angle);
    peak = EstimateTranslation(rotated, n, coarse_level, coarse ? &*coarse : nullptr, &full,
                               options, residual->shift);
  }
  result.shift = peak.position;
  result.rotation_rad = angle;
  result.peak = peak.height;
  return result;
}

}  // namespace pipescope
