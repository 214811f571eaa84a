#include "pipescope/dense/dense_pair_registration.h"

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "pipescope/dense/dense_image.h"
#include "pipescope/util/error.h"

namespace pipescope {
namespace {

struct MethodName {
  DenseMethod method;
  const char* name;
};

constexpr MethodName kMethodNames[] = {
    {DenseMethod::kSad, "dense-sad"},           {DenseMethod::kSsd, "dense-ssd"},
    {DenseMethod::kZncc, "dense-zncc"},         {DenseMethod::kLucasKanade, "dense-lk"},
    {DenseMethod::kHybrid, "dense-hybrid"},     {DenseMethod::kPhase, "phase"},
    {DenseMethod::kUnrolled, "dense-unrolled"}, {DenseMethod::kOpenCvPhase, "opencv-phase"},
};

PairMotion FullSearchMotion(FullSearchCost cost, const cv::Mat& reference, const cv::Mat& next,
                            const FullSearchOptions& base) {
  FullSearchOptions options = base;
  options.cost = cost;
  const FullSearchResult result = RegisterFullSearch(reference, next, options);
  PairMotion motion;
  motion.shift = result.shift;
  motion.rounding_residual = RoundingResidual(result);
  if (!std::isfinite(result.cost)) {
    motion.failure = "no shift in the search window has enough overlap";
  } else if (std::abs(result.shift.x) == result.max_shift_x_px ||
             std::abs(result.shift.y) == result.max_shift_y_px) {
    // A minimum on the window's edge is most likely outside it (motion faster than the window).
    motion.failure = "best shift on the search window's edge";
  }
  return motion;
}

// The pair cut to its overlap at the predicted shift rounded to whole pixels, reference(R) and
// next(R + offset): a search around zero there is a search around the prediction in the whole
// frames. 000 Algorithm 1 centres the window on zero motion, which bounds the shift from a key
// frame by the window; centred on the prediction, a key frame can be kept for far longer, and
// integer rounding then accrues once per key frame. No cut (offset 0) when the overlap would be
// under a quarter of the frame or 16 px across.
struct PairAtOffset {
  cv::Mat reference, next;
  cv::Point offset;
};

PairAtOffset CutToOverlap(const cv::Mat& reference, const cv::Mat& next, cv::Point2d predicted) {
  const cv::Point offset(static_cast<int>(std::lround(predicted.x)),
                         static_cast<int>(std::lround(predicted.y)));
  const cv::Rect overlap = OverlapAtShift(reference.size(), offset);
  if (offset == cv::Point(0, 0) || overlap.width < 16 || overlap.height < 16 ||
      overlap.area() < reference.size().area() / 4) {
    return {reference, next, cv::Point(0, 0)};
  }
  return {reference(overlap), next(overlap + offset), offset};
}

}  // namespace

const std::vector<std::string>& DenseMethodNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> result;
    for (const MethodName& entry : kMethodNames) result.push_back(entry.name);
    return result;
  }();
  return names;
}

std::string DenseMethodName(DenseMethod method) {
  for (const MethodName& entry : kMethodNames) {
    if (entry.method == method) return entry.name;
  }
  return "unknown";
}

DenseMethod ParseDenseMethod(const std::string& name) {
  for (const MethodName& entry : kMethodNames) {
    if (name == entry.name) return entry.method;
  }
  std::string valid;
  for (const std::string& known : DenseMethodNames()) valid += (valid.empty() ? "" : ", ") + known;
  throw InputError("--method: unknown dense method '" + name + "' (valid: " + valid + ")");
}

double OverlapCorrelation(const cv::Mat& reference, const cv::Mat& next, cv::Point2d shift) {
  const cv::Point t(static_cast<int>(std::lround(shift.x)), static_cast<int>(std::lround(shift.y)));
  const cv::Rect reference_area = OverlapAtShift(reference.size(), t);
  if (reference_area.area() < 4) return 0.0;
  const cv::Mat a = reference(reference_area);
  const cv::Mat b = next(reference_area + t);
  // OpenCV scores a constant template 1; a uniform overlap (a black frame) matches nothing.
  cv::Scalar mean_a, deviation_a, mean_b, deviation_b;
  cv::meanStdDev(a, mean_a, deviation_a);
  cv::meanStdDev(b, mean_b, deviation_b);
  if (!(deviation_a[0] > 0.0 && deviation_b[0] > 0.0)) return 0.0;
  cv::Mat result;
  cv::matchTemplate(a, b, result, cv::TM_CCOEFF_NORMED);
  const double value = result.at<float>(0, 0);
  return std::isfinite(value) ? value : 0.0;
}

PairMotion RegisterPlanarPair(DenseMethod method, const cv::Mat& reference, const cv::Mat& next,
                              const PairRegistrationOptions& options, cv::Point2d predicted_shift,
                              double predicted_rotation_rad) {
  PairMotion motion;
  switch (method) {
    case DenseMethod::kSad:
    case DenseMethod::kSsd:
    case DenseMethod::kZncc: {
      const FullSearchCost cost = method == DenseMethod::kSad   ? FullSearchCost::kSad
                                  : method == DenseMethod::kSsd ? FullSearchCost::kSsd
                                                                : FullSearchCost::kZncc;
      const PairAtOffset pair = CutToOverlap(reference, next, predicted_shift);
      motion = FullSearchMotion(cost, pair.reference, pair.next, options.full_search);
      motion.shift += cv::Point2d(pair.offset);
      break;
    }
    case DenseMethod::kLucasKanade: {
      const LucasKanadeResult result =
          RegisterLucasKanade(reference, next, options.lucas_kanade, predicted_shift);
      motion.shift = result.shift;
      if (!result.converged) motion.failure = "Gauss-Newton did not converge";
      break;
    }
    case DenseMethod::kHybrid: {
      HybridOptions hybrid = options.hybrid;
      hybrid.full_search = options.full_search;
      const PairAtOffset pair = CutToOverlap(reference, next, predicted_shift);
      const HybridResult result = RegisterHybrid(pair.reference, pair.next, hybrid);
      motion.shift = result.shift + cv::Point2d(pair.offset);
      // Still means no motion from the reference, not none from the prediction.
      motion.still = result.still && pair.offset == cv::Point(0, 0);
      motion.integer_only = !result.refined && !motion.still;
      if (std::abs(result.integer_shift.x) == options.full_search.max_shift_x_px ||
          std::abs(result.integer_shift.y) == options.full_search.max_shift_y_px) {
        motion.failure = "best shift on the search window's edge";
      }
      break;
    }
    case DenseMethod::kPhase: {
      const PhaseCorrelationResult result =
          RegisterPhaseCorrelation(reference, next, options.phase, predicted_rotation_rad);
      motion.shift = result.shift;
      motion.rotation_rad = result.rotation_rad;
      // A still camera stays still (000 §4.2.3): phase correlation has no still test of its own,
      // so a translation-only shift below the hybrid method's still_shift_px is taken as none.
      // The pipeline registers to key frames, so what this drops never accrues.
      if (!options.phase.estimate_rotation &&
          std::hypot(motion.shift.x, motion.shift.y) < options.hybrid.still_shift_px) {
        motion.shift = cv::Point2d(0.0, 0.0);
        motion.still = true;
      }
      break;
    }
    case DenseMethod::kOpenCvPhase: {
      // What a user would write in an afternoon: OpenCV's phase correlation with a Hann window.
      cv::Mat window;
      cv::createHanningWindow(window, reference.size(), CV_32F);
      cv::Mat reference_float, next_float;
      reference.convertTo(reference_float, CV_32F);
      next.convertTo(next_float, CV_32F);
      motion.shift = cv::phaseCorrelate(reference_float, next_float, window);
      break;
    }
    case DenseMethod::kUnrolled:
      throw std::logic_error("RegisterPlanarPair: dense-unrolled registers unrolled frames");
  }
  motion.correlation = OverlapCorrelation(reference, next, motion.shift);
  if (motion.failure.empty() && motion.correlation < options.min_correlation) {
    motion.failure = "overlap correlation " + std::to_string(motion.correlation) + " below " +
                     std::to_string(options.min_correlation);
  }
  return motion;
}

}  // namespace pipescope
