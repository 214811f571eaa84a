// Simulator throughput per preset at its native size, on all cores. Target (issue 3): at least
// 30 frames/s at 640x480.
//  - BM_RenderFrame: one frame of radiance, then the sensor, one after the other (PNG encoding
//    excluded).
//  - BM_SimulateLoop: the loop of `pipescope simulate` without the disk: while frame i + 1
//    renders on all cores, frame i goes through the sensor and the PNG encoder on another
//    thread, as SimulateDataset() does.
#include <benchmark/benchmark.h>

#include <future>
#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "pipescope/synthetic/presets.h"
#include "pipescope/synthetic/sensor.h"
#include "pipescope/synthetic/simulation.h"

namespace pipescope {
namespace {

SimulationConfig BenchConfig(const std::string& preset) {
  SimulationConfig config = PresetConfig(preset);
  config.frames = 1000;
  return config;
}

void Label(benchmark::State& state, const SimulationConfig& config) {
  state.counters["frames_per_s"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.SetLabel(std::to_string(config.width) + "x" + std::to_string(config.height) + " " +
                 config.camera_model);
}

void BM_RenderFrame(benchmark::State& state, const std::string& preset) {
  const SimulationConfig config = BenchConfig(preset);
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
  Label(state, config);
}

void BM_SimulateLoop(benchmark::State& state, const std::string& preset) {
  const SimulationConfig config = BenchConfig(preset);
  const Simulation simulation(config);
  const cv::Mat vignetting = VignettingMap(simulation.camera(), config.vignetting);
  SensorOptions sensor;
  sensor.exposure = 1000.0;
  int frame = 0;
  std::future<std::size_t> pending;
  for (auto _ : state) {
    cv::Mat radiance = simulation.RenderFrameRadiance(frame);
    if (pending.valid()) benchmark::DoNotOptimize(pending.get());
    pending = std::async(std::launch::async, [&, frame, radiance = std::move(radiance)] {
      std::vector<std::uint8_t> png;
      cv::imencode(".png", ApplySensor(radiance, vignetting, sensor, frame), png,
                   {cv::IMWRITE_PNG_COMPRESSION, 1, cv::IMWRITE_PNG_STRATEGY,
                    cv::IMWRITE_PNG_STRATEGY_HUFFMAN_ONLY});  // as SimulateDataset() writes
      return png.size();
    });
    frame = (frame + 7) % config.frames;
  }
  pending.get();
  Label(state, config);
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
BENCHMARK_CAPTURE(BM_SimulateLoop, steel_16in, std::string("steel-16in"))
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_SimulateLoop, culvert, std::string("culvert"))
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_SimulateLoop, tube_bend, std::string("tube-bend"))
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace pipescope
