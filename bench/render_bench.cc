// Simulator throughput: one frame (radiance, sensor, PNG encoding excluded) per preset at its
// native size, on all cores. Target (issue 3): at least 30 frames/s at 640x480.
#include <benchmark/benchmark.h>

#include "pipescope/synthetic/presets.h"
#include "pipescope/synthetic/sensor.h"
#include "pipescope/synthetic/simulation.h"

namespace pipescope {
namespace {

void BM_RenderFrame(benchmark::State& state, const std::string& preset) {
  SimulationConfig config = PresetConfig(preset);
  config.frames = 1000;
  const Simulation simulation(config);
  const cv::Mat vignetting = VignettingMap(simulation.camera(), config.vignetting);
  SensorOptions sensor;
  sensor.exposure = 1000.0;
  int frame = 0;
  for (auto _ : state) {
    const cv::Mat radiance = simulation.RenderFrameRadiance(frame);
    benchmark::DoNotOptimize(ApplySensor(radiance, vignetting, sensor, frame));
    frame = (frame + 7) % config.frames;
  }
  state.counters["frames_per_s"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.SetLabel(std::to_string(config.width) + "x" + std::to_string(config.height) + " " +
                 config.camera_model);
}

BENCHMARK_CAPTURE(BM_RenderFrame, steel_6in, std::string("steel-6in"))
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_RenderFrame, steel_16in, std::string("steel-16in"))
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_RenderFrame, fiberglass_network, std::string("fiberglass-network"))
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_RenderFrame, culvert, std::string("culvert"))
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_RenderFrame, tube_bend, std::string("tube-bend"))
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace pipescope
