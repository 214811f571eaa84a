// The simulator's per-pixel kernels: a ray cast into the scene and a texture sample. The
// renderer calls each once per pixel per frame.
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "pipescope/synthetic/presets.h"
#include "pipescope/synthetic/scene_layouts.h"
#include "pipescope/synthetic/wall_texture.h"

namespace pipescope {
namespace {

// Rays of a 190-degree forward fan from a point on the route, the fisheye network's worst case.
void BM_Intersect(benchmark::State& state, const std::string& preset) {
  const Layout layout = BuildLayout(PresetConfig(preset));
  Eigen::Vector3d origin, forward;
  layout.route.Evaluate(layout.start_s_m + 0.3, &origin, &forward);
  const Eigen::Quaterniond to_route =
      Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), forward);
  std::vector<Ray> rays;
  for (int row = 0; row < 200; ++row) {
    for (int col = 0; col < 200; ++col) {
      const double x = col / 99.5 - 1.0, y = row / 99.5 - 1.0;
      const double theta = std::hypot(x, y) * 95.0 * M_PI / 180.0, psi = std::atan2(y, x);
      const Eigen::Vector3d cam(std::sin(theta) * std::cos(psi), std::sin(theta) * std::sin(psi),
                                std::cos(theta));
      rays.push_back({origin, to_route * cam});
    }
  }
  for (auto _ : state) {
    for (const Ray& ray : rays) benchmark::DoNotOptimize(layout.scene.Intersect(ray));
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(rays.size()));
}

// Coherent 160 x 120 tiles at a 0.1 mm footprint, the way the renderer walks the wall.
void BM_TextureSample(benchmark::State& state, const std::string& material) {
  WallTextureOptions options;
  options.material = WallMaterialFromName(material);
  options.joint_spacing_m = 1.5;
  const WallTexture texture(options);
  const double circumference = 2.0 * M_PI * 0.2;
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (auto _ : state) {
    const double h0 = 6.0 * unit(rng), s0 = circumference * unit(rng);
    for (int row = 0; row < 120; ++row) {
      for (int col = 0; col < 160; ++col) {
        benchmark::DoNotOptimize(
            texture.Sample(0, h0 + 1e-4 * col, s0 + 1e-4 * row, circumference, 1e-4));
      }
    }
  }
  state.SetItemsProcessed(state.iterations() * 160 * 120);
}

BENCHMARK_CAPTURE(BM_Intersect, straight, std::string("steel-16in"));
BENCHMARK_CAPTURE(BM_Intersect, bend_tube, std::string("tube-bend"));
BENCHMARK_CAPTURE(BM_Intersect, four_tee_loop, std::string("fiberglass-network"));
BENCHMARK_CAPTURE(BM_TextureSample, steel, std::string("steel"));
BENCHMARK_CAPTURE(BM_TextureSample, fiberglass, std::string("fiberglass"));
BENCHMARK_CAPTURE(BM_TextureSample, concrete, std::string("concrete"));

}  // namespace
}  // namespace pipescope
