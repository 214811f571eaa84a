#pragma once

#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "pipescope/dense/full_search.h"
#include "pipescope/dense/hybrid_registration.h"
#include "pipescope/dense/lucas_kanade.h"
#include "pipescope/dense/phase_correlation.h"

namespace pipescope {

// The dense odometry methods of `pipescope odometry` (GUIDE §5).
enum class DenseMethod {
  kSad,          // dense-sad: full search, SAD (000 Algorithm 1, eq. 13)
  kSsd,          // dense-ssd: eq. 14
  kZncc,         // dense-zncc: eq. 15-17
  kLucasKanade,  // dense-lk: hierarchical Gauss-Newton (000 eq. 20-27)
  kHybrid,       // dense-hybrid: full search, then Gauss-Newton at full resolution (000 §4.2.3)
  kPhase,        // phase: phase correlation with rotation (003 eq. 5-7)
  kUnrolled,     // dense-unrolled: registration on the unrolled wall (beyond the papers)
  kOpenCvPhase,  // opencv-phase: cv::phaseCorrelate, the baseline of issue 5's benchmark
};

const std::vector<std::string>& DenseMethodNames();
std::string DenseMethodName(DenseMethod method);
// Throws InputError naming --method and the valid names for an unknown name.
DenseMethod ParseDenseMethod(const std::string& name);

struct PairRegistrationOptions {
  FullSearchOptions full_search = [] {
    FullSearchOptions options;
    // Two pyramid levels keep SAD at the speed the pipelines need (docs/dense_registration.md);
    // 0 searches exhaustively as 000 does.
    options.pyramid_levels = 2;
    return options;
  }();
  LucasKanadeOptions lucas_kanade;
  HybridOptions hybrid;
  // `phase` registers the translation only unless asked for 003's rotation (eq. 7,
  // `phase_rotation: true`), which a robot that turns needs, such as 003's on the culvert floor.
  // A crawler in a pipe cannot keep a heading off the axis, and integrating a measured rotation
  // random-walks the heading: steel-16in seed 2, 0.09 degrees of noise per key frame, drifted to
  // -3.4 degrees while the truth stayed within +-0.6, and the run came back 2.6 % of its length
  // off its start against 0.002 % without rotation (docs/dense_vo.md).
  PhaseCorrelationOptions phase;
  // A pair whose overlap correlates (ZNCC at the estimated shift) below this is a failed
  // registration: too little texture, blur or a lighting artefact dominated.
  double min_correlation = 0.3;
};

// The image motion between two prepared frames: next(R(rotation)(x - c) + c + shift) =
// reference(x), c the image centre (dense/phase_correlation.h); rotation is 0 except for `phase`.
struct PairMotion {
  cv::Point2d shift;
  double rotation_rad = 0.0;
  double correlation = 0.0;  // ZNCC of the overlap at the rounded shift
  bool still = false;        // dense-hybrid or phase (translation only) reported no motion
  // dense-hybrid: the Gauss-Newton refinement did not converge or moved too far
  // (HybridOptions::max_refinement_px), so the full search's whole-pixel shift was kept.
  bool integer_only = false;
  std::string failure;  // why the pair cannot be used; empty when it can
  // The integer full searches (dense-sad, -ssd, -zncc) only: how far the cost's minimum lies
  // from the reported whole-pixel shift (dense/full_search.h RoundingResidual).
  std::optional<cv::Point2d> rounding_residual;
};

// Registers a pair of prepared frames with one of the planar methods (every method but
// kUnrolled). `predicted_shift` (the previous pair's) centres the full search's window (dense-sad,
// -ssd, -zncc, -hybrid) and seeds dense-lk; `predicted_rotation_rad`
// starts phase correlation's rotation search.
PairMotion RegisterPlanarPair(DenseMethod method, const cv::Mat& reference, const cv::Mat& next,
                              const PairRegistrationOptions& options, cv::Point2d predicted_shift,
                              double predicted_rotation_rad = 0.0);

// ZNCC of reference(x) and next(x + shift) over their overlap (shift rounded to whole pixels);
// 0 when the overlap is empty or flat.
double OverlapCorrelation(const cv::Mat& reference, const cv::Mat& next, cv::Point2d shift);

}  // namespace pipescope
