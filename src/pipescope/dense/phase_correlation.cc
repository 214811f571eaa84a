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
Peak EstimateTranslation(const cv::Mat& reference, const cv::Mat& next, int coarse_level,
                         const Level* coarse, std::optional<Level>* full,
                         const PhaseCorrelationOptions& options) {
  auto whole_images = [&] {
    if (!full->has_value()) full->emplace(next, options);
    return FindPeak((*full)->With(reference), options.peak_method);
  };
  if (!options.refine_on_overlap) return whole_images();
  cv::Point2d estimate;
  if (coarse_level > 0) {
    const cv::Mat reference_coarse = BuildGaussianPyramid(reference, coarse_level + 1).back();
    estimate = FindPeak(coarse->With(reference_coarse), PhasePeakMethod::kParabolic).position *
               static_cast<double>(1 << coarse_level);
  } else {
    if (!full->has_value()) full->emplace(next, options);
    estimate = FindPeak((*full)->With(reference), PhasePeakMethod::kParabolic).position;
  }
  const cv::Point shift(static_cast<int>(std::lround(estimate.x)),
                        static_cast<int>(std::lround(estimate.y)));
  const cv::Rect overlap(std::max(0, -shift.x), std::max(0, -shift.y),
                         reference.cols - std::abs(shift.x), reference.rows - std::abs(shift.y));
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
                                                const PhaseCorrelationOptions& options) {
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

  // Rotation search (003 eq. 7), scored by the height of the (parabolic) peak: every step of the
  // range on the coarse level, where each correlation is cheap and the peak falls off more
  // gently with angle, then parabolic refinements at full resolution.
  auto score = [](const Level& level, const cv::Mat& reference_level, double angle) {
    return FindPeak(level.With(RotateAboutCentre(reference_level, angle)),
                    PhasePeakMethod::kParabolic)
        .height;
  };
  const cv::Mat r_coarse = BuildGaussianPyramid(r, coarse_level + 1).back();
  if (!full.has_value()) full.emplace(n, options);
  const Level& search_level = coarse_level > 0 ? *coarse : *full;
  const double step = std::max(1e-6, options.rotation_step_rad);
  const int steps = std::max(0, static_cast<int>(std::floor(options.max_rotation_rad / step)));
  std::vector<double> scores;
  for (int k = -steps; k <= steps; ++k) scores.push_back(score(search_level, r_coarse, k * step));
  const int best =
      static_cast<int>(std::max_element(scores.begin(), scores.end()) - scores.begin());
  double angle = (best - steps) * step;
  double offset, height;
  if (best > 0 && best + 1 < static_cast<int>(scores.size())) {
    ParabolaVertex(scores[best - 1], scores[best], scores[best + 1], &offset, &height);
    angle += offset * step;
  }
  double spacing = step;
  for (int refinement = 0; refinement < options.rotation_refinements; ++refinement) {
    spacing *= 0.5;
    ParabolaVertex(score(*full, r, angle - spacing), score(*full, r, angle),
                   score(*full, r, angle + spacing), &offset, &height);
    angle += offset * spacing;
  }
  angle = std::clamp(angle, -steps * step, steps * step);
  const Peak peak = EstimateTranslation(RotateAboutCentre(r, angle), n, coarse_level,
                                        coarse ? &*coarse : nullptr, &full, options);
  result.shift = peak.position;
  result.rotation_rad = angle;
  result.peak = peak.height;
  return result;
}

}  // namespace pipescope
