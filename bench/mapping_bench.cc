// Mapping kernels: the unrolling maps of one frame (built once per frame by dense-unrolled
// odometry and by the unrolled mosaic) and the resampling through them, one core, at the
// quarter-resolution grid of 000 (256x192) and at 640x480.
#include <benchmark/benchmark.h>

#include <cmath>
#include <opencv2/core.hpp>

#include "pipescope/image/wall_unrolling.h"

namespace pipescope {
namespace {

// A wall-looking 640x480 camera with mild distortion in the 16-inch pipe of 000, and a grid at
// the image's own resolution around the wall point it looks at.
struct Setup {
  Camera camera{CameraModelId::kPinholeRadtan,
                640,
                480,
                {1443.0, 1443.0, 319.5, 239.5, 0.05, 0.01, 0.0, 0.0, 0.0}};
  Eigen::Isometry3d world_from_cam = Eigen::Isometry3d::Identity();
  UnrolledGrid grid;

  explicit Setup(const benchmark::State& state) {
    world_from_cam.linear().col(0) = Eigen::Vector3d::UnitZ();
    world_from_cam.linear().col(1) = Eigen::Vector3d::UnitX();
    world_from_cam.linear().col(2) = Eigen::Vector3d::UnitY();
    world_from_cam.translation() = Eigen::Vector3d(0.004, 0.0, 1.0);
    const double radius = 0.19378;
    const cv::Size size(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
    const double pixel = 0.06 / size.width;  // the frame's footprint is ~85 x 64 mm
    grid = {radius, 1.0 - 0.5 * size.width * pixel, radius * M_PI / 2 - 0.5 * size.height * pixel,
            pixel, size};
  }
};

void BM_BuildUnrollingMaps(benchmark::State& state) {
  cv::setNumThreads(1);
  const Setup setup(state);
  cv::Mat map_x, map_y;
  for (auto _ : state) {
    BuildUnrollingMaps(setup.camera, setup.world_from_cam, setup.grid, &map_x, &map_y);
    benchmark::DoNotOptimize(map_x.data);
  }
  state.SetItemsProcessed(state.iterations() * setup.grid.size.area());  // cells per second
}

void BM_UnrollFrame(benchmark::State& state) {
  cv::setNumThreads(1);
  const Setup setup(state);
  cv::Mat map_x, map_y, valid;
  BuildUnrollingMaps(setup.camera, setup.world_from_cam, setup.grid, &map_x, &map_y);
  cv::Mat frame(480, 640, CV_32F);
  cv::randu(frame, 0.0, 255.0);
  for (auto _ : state) {
    const cv::Mat unrolled = UnrollFrame(frame, map_x, map_y, &valid);
    benchmark::DoNotOptimize(unrolled.data);
  }
  state.SetItemsProcessed(state.iterations() * setup.grid.size.area());
}

BENCHMARK(BM_BuildUnrollingMaps)->Args({256, 192})->Args({640, 480})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_UnrollFrame)->Args({256, 192})->Args({640, 480})->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace pipescope
