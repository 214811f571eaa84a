// Dense registration kernels (000 §4, 003 §2.3): one frame pair per iteration, one core, at the
// quarter-resolution sizes of 000 (256x192 for pipe 1, 160x120 for pipe 2) and at 640x480.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "pipescope/dense/full_search.h"
#include "pipescope/dense/hybrid_registration.h"
#include "pipescope/dense/lucas_kanade.h"
#include "pipescope/dense/phase_correlation.h"
#include "pipescope/dense/testing.h"

namespace pipescope {
namespace {

cv::Size SizeOf(const benchmark::State& state) {
  return {static_cast<int>(state.range(0)), static_cast<int>(state.range(1))};
}

// A textured pair moved by a typical inter-frame motion: 6 % of the width along the pipe axis
// (image x), a little across.
RegistrationPair PairFor(const benchmark::State& state) {
  const cv::Size size = SizeOf(state);
  return MakeRegistrationPair(size, {0.063 * size.width, -0.013 * size.height}, 0.0, 1.0, 1);
}

// The search window scales with the image: the defaults (+-32, +-16 px) at 256x192.
FullSearchOptions SearchOptionsFor(const benchmark::State& state, FullSearchCost cost) {
  FullSearchOptions options;
  options.cost = cost;
  options.max_shift_x_px = state.range(0) / 8;
  options.max_shift_y_px = state.range(0) / 16;
  return options;
}

void SetLabel(benchmark::State& state, const std::string& what) {
  state.SetLabel(what + " " + std::to_string(state.range(0)) + "x" +
                 std::to_string(state.range(1)));
  state.SetItemsProcessed(state.iterations());  // items/s = frame pairs per second
}

void BM_FullSearch(benchmark::State& state, FullSearchCost cost, int pyramid_levels) {
  cv::setNumThreads(1);
  const RegistrationPair pair = PairFor(state);
  FullSearchOptions options = SearchOptionsFor(state, cost);
  options.pyramid_levels = pyramid_levels;
  for (auto _ : state) {
    benchmark::DoNotOptimize(RegisterFullSearch(pair.reference, pair.next, options));
  }
  SetLabel(state, std::string(FullSearchCostName(cost)) +
                      (pyramid_levels > 0 ? " pyramid " + std::to_string(pyramid_levels) : "") +
                      " window +-" + std::to_string(options.max_shift_x_px) + "x+-" +
                      std::to_string(options.max_shift_y_px));
}

void BM_LucasKanade(benchmark::State& state) {
  cv::setNumThreads(1);
  const RegistrationPair pair = PairFor(state);
  for (auto _ : state) {
    benchmark::DoNotOptimize(RegisterLucasKanade(pair.reference, pair.next));
  }
  SetLabel(state, "lk");
}

void BM_Hybrid(benchmark::State& state, FullSearchCost cost, int pyramid_levels) {
  cv::setNumThreads(1);
  const RegistrationPair pair = PairFor(state);
  HybridOptions options;
  options.full_search = SearchOptionsFor(state, cost);
  options.full_search.pyramid_levels = pyramid_levels;
  for (auto _ : state) {
    benchmark::DoNotOptimize(RegisterHybrid(pair.reference, pair.next, options));
  }
  SetLabel(state, std::string("hybrid ") + FullSearchCostName(cost) +
                      (pyramid_levels > 0 ? " pyramid " + std::to_string(pyramid_levels) : ""));
}

void BM_Phase(benchmark::State& state, bool rotation) {
  cv::setNumThreads(1);
  const RegistrationPair pair = PairFor(state);
  PhaseCorrelationOptions options;
  options.estimate_rotation = rotation;
  for (auto _ : state) {
    benchmark::DoNotOptimize(RegisterPhaseCorrelation(pair.reference, pair.next, options));
  }
  SetLabel(state, rotation ? "phase + rotation" : "phase");
}

// The baseline of issue 5: OpenCV's own phase correlation with a Hann window.
void BM_OpenCvPhaseCorrelate(benchmark::State& state) {
  cv::setNumThreads(1);
  const RegistrationPair pair = PairFor(state);
  cv::Mat window;
  cv::createHanningWindow(window, pair.reference.size(), CV_32F);
  for (auto _ : state) {
    benchmark::DoNotOptimize(cv::phaseCorrelate(pair.reference, pair.next, window));
  }
  SetLabel(state, "cv::phaseCorrelate");
}

// Accuracy on 30 random pairs (shifts up to +-12 % of the width and +-6 % of the height, noise
// sigma 1 on a texture of standard deviation ~30; with rotation, up to +-8 degrees): the RMS and
// the largest error in pixels (and degrees), as counters. One iteration each.
enum class Method { kLucasKanade, kHybrid, kPhase, kPhaseRotation, kOpenCv };

void BM_Accuracy(benchmark::State& state, Method method) {
  cv::setNumThreads(1);
  const cv::Size size = SizeOf(state);
  constexpr int kPairs = 30;
  constexpr double kDeg = std::numbers::pi / 180.0;
  double sum_squared = 0, max_error = 0, sum_squared_deg = 0, max_error_deg = 0;
  for (auto _ : state) {
    cv::RNG rng(11);
    for (int i = 0; i < kPairs; ++i) {
      const cv::Point2d shift(rng.uniform(-0.12, 0.12) * size.width,
                              rng.uniform(-0.06, 0.06) * size.height);
      const double angle = method == Method::kPhaseRotation ? rng.uniform(-8.0, 8.0) * kDeg : 0.0;
      const RegistrationPair pair = MakeRegistrationPair(size, shift, angle, 1.0, 1000 + i);
      cv::Point2d estimate;
      double estimate_angle = 0.0;
      switch (method) {
        case Method::kLucasKanade:
          estimate = RegisterLucasKanade(pair.reference, pair.next).shift;
          break;
        case Method::kHybrid: {
          HybridOptions options;
          options.full_search = SearchOptionsFor(state, FullSearchCost::kSad);
          estimate = RegisterHybrid(pair.reference, pair.next, options).shift;
          break;
        }
        case Method::kPhase:
          estimate = RegisterPhaseCorrelation(pair.reference, pair.next).shift;
          break;
        case Method::kPhaseRotation: {
          PhaseCorrelationOptions options;
          options.estimate_rotation = true;
          const PhaseCorrelationResult result =
              RegisterPhaseCorrelation(pair.reference, pair.next, options);
          estimate = result.shift;
          estimate_angle = result.rotation_rad;
          break;
        }
        case Method::kOpenCv: {
          cv::Mat window;
          cv::createHanningWindow(window, size, CV_32F);
          estimate = cv::phaseCorrelate(pair.reference, pair.next, window);
          break;
        }
      }
      const double error = std::hypot(estimate.x - shift.x, estimate.y - shift.y);
      sum_squared += error * error;
      max_error = std::max(max_error, error);
      const double error_deg = std::abs(estimate_angle - angle) / kDeg;
      sum_squared_deg += error_deg * error_deg;
      max_error_deg = std::max(max_error_deg, error_deg);
    }
  }
  state.counters["rms_px"] = std::sqrt(sum_squared / kPairs);
  state.counters["max_px"] = max_error;
  if (method == Method::kPhaseRotation) {
    state.counters["rms_deg"] = std::sqrt(sum_squared_deg / kPairs);
    state.counters["max_deg"] = max_error_deg;
  }
  state.SetLabel(std::to_string(size.width) + "x" + std::to_string(size.height));
}

// The presets' prepared frames (160x120, 256x192), a full 640x480 frame, and the half-height
// bands the odometry registers by default (160x60, 256x96).
void Sizes(benchmark::internal::Benchmark* b) {
  b->Args({160, 120})->Args({256, 192})->Args({640, 480})->Args({160, 60})->Args({256, 96});
  b->Unit(benchmark::kMillisecond);
}

BENCHMARK_CAPTURE(BM_FullSearch, sad, FullSearchCost::kSad, 0)->Apply(Sizes);
BENCHMARK_CAPTURE(BM_FullSearch, sad_pyramid2, FullSearchCost::kSad, 2)->Apply(Sizes);
BENCHMARK_CAPTURE(BM_FullSearch, ssd, FullSearchCost::kSsd, 0)->Apply(Sizes);
BENCHMARK_CAPTURE(BM_FullSearch, zncc, FullSearchCost::kZncc, 0)->Apply(Sizes);
BENCHMARK(BM_LucasKanade)->Apply(Sizes);
BENCHMARK_CAPTURE(BM_Hybrid, sad, FullSearchCost::kSad, 0)->Apply(Sizes);
BENCHMARK_CAPTURE(BM_Hybrid, sad_pyramid2, FullSearchCost::kSad, 2)->Apply(Sizes);
BENCHMARK_CAPTURE(BM_Hybrid, zncc, FullSearchCost::kZncc, 0)->Apply(Sizes);
BENCHMARK_CAPTURE(BM_Phase, translation, false)->Apply(Sizes);
BENCHMARK_CAPTURE(BM_Phase, rotation, true)->Apply(Sizes);
BENCHMARK(BM_OpenCvPhaseCorrelate)->Apply(Sizes);

void AccuracySizes(benchmark::internal::Benchmark* b) {
  b->Args({160, 120})->Args({256, 192})->Args({160, 60})->Args({256, 96});
  b->Iterations(1)->Unit(benchmark::kMillisecond);
}

BENCHMARK_CAPTURE(BM_Accuracy, lk, Method::kLucasKanade)->Apply(AccuracySizes);
BENCHMARK_CAPTURE(BM_Accuracy, hybrid_sad, Method::kHybrid)->Apply(AccuracySizes);
BENCHMARK_CAPTURE(BM_Accuracy, phase, Method::kPhase)->Apply(AccuracySizes);
BENCHMARK_CAPTURE(BM_Accuracy, phase_rotation, Method::kPhaseRotation)->Apply(AccuracySizes);
BENCHMARK_CAPTURE(BM_Accuracy, opencv_phase_correlate, Method::kOpenCv)->Apply(AccuracySizes);

}  // namespace
}  // namespace pipescope
