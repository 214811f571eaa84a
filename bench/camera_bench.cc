// Per-pixel cost of the camera models: every renderer and estimator calls these in its inner
// loop.
#include <benchmark/benchmark.h>

#include <Eigen/Core>
#include <vector>

#include "pipescope/camera/camera.h"

namespace pipescope {
namespace {

Camera MakeCamera(int model) {
  switch (model) {
    case 0:
      return Camera(CameraModelId::kPinholeRadtan, 1024, 768,
                    {731.0, 731.0, 511.5, 383.5, -0.2, 0.05, 1e-4, -2e-4, 0.0});
    case 1:
      return Camera(CameraModelId::kKannalaBrandt, 1024, 768,
                    {731.0, 731.0, 511.5, 383.5, 0.05, -0.01, 0.002, -0.0005});
    default:
      return Camera(CameraModelId::kFisheyePoly, 1280, 960, {410.0, -8.0, 1.0, -0.2, 639.5, 479.5});
  }
}

std::vector<Eigen::Vector2d> PixelGrid(const Camera& camera) {
  std::vector<Eigen::Vector2d> pixels;
  for (int y = 0; y < camera.Height(); y += 16) {
    for (int x = 0; x < camera.Width(); x += 16) pixels.emplace_back(x, y);
  }
  return pixels;
}

void BM_Unproject(benchmark::State& state) {
  const Camera camera = MakeCamera(static_cast<int>(state.range(0)));
  const std::vector<Eigen::Vector2d> pixels = PixelGrid(camera);
  Eigen::Vector3d bearing;
  for (auto _ : state) {
    for (const Eigen::Vector2d& pixel : pixels) {
      benchmark::DoNotOptimize(camera.Unproject(pixel, &bearing));
    }
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(pixels.size()));
  state.SetLabel(camera.ModelName());
}

void BM_Project(benchmark::State& state) {
  const Camera camera = MakeCamera(static_cast<int>(state.range(0)));
  std::vector<Eigen::Vector3d> bearings;
  Eigen::Vector3d bearing;
  for (const Eigen::Vector2d& pixel : PixelGrid(camera)) {
    if (camera.Unproject(pixel, &bearing)) bearings.push_back(bearing);
  }
  Eigen::Vector2d pixel;
  for (auto _ : state) {
    for (const Eigen::Vector3d& point : bearings) {
      benchmark::DoNotOptimize(camera.Project(point, &pixel));
    }
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(bearings.size()));
  state.SetLabel(camera.ModelName());
}

BENCHMARK(BM_Unproject)->DenseRange(0, 2);
BENCHMARK(BM_Project)->DenseRange(0, 2);

}  // namespace
}  // namespace pipescope
