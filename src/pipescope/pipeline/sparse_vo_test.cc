#include "pipescope/pipeline/sparse_vo.h"

#include <gtest/gtest.h>

#include <cmath>

#include "pipescope/camera/camera_io.h"
#include "pipescope/eval/trajectory_metrics.h"
#include "pipescope/io/dataset.h"
#include "pipescope/synthetic/dataset_writer.h"
#include "pipescope/synthetic/presets.h"
#include "pipescope/synthetic/simulation_config.h"
#include "pipescope/util/error.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

// 000 Table 1's pipe 2 set-up at half resolution (320x240, 25 degrees), one way, 2 s at
// 10 cm/s, with the preset's drift across the pipe, roll and wobble; small, so the test is fast.
std::filesystem::path ShortSteelRun() {
  static const std::filesystem::path path = [] {
    const auto dir = MakeTestDirectory("sparse_vo_short") / "steel";
    SimulationConfig config = PresetConfig("steel-16in");
    config.width = 320;
    config.height = 240;
    config.frames = 60;
    config.out_and_back = false;
    config.speed_m_s = 0.1;
    config.white_card_count = 4;
    SimulateDataset(config, dir);
    return dir;
  }();
  return path;
}

TEST(SparseVo, ShortRunStaysWithinBound) {
  const DatasetManifest manifest = OpenDataset(ShortSteelRun());
  const Camera camera = ReadCamera(manifest.camera_path);
  SparseVoOptions options;
  options.build_mosaic = false;
  options.refine_every = 5;  // so the short run exercises the 6-DOF refinement
  // 000's sigma_W = 3, sigma_D = 1.5 are for 640x480 frames; these are half that size.
  options.harris.sigma_window_px = 1.5;
  options.harris.sigma_derivative_px = 0.75;
  const SparseVoResult result = RunSparseVo(manifest, camera, options);
  EXPECT_EQ(result.trajectory.size(), 60u);  // every frame has a pose
  EXPECT_GE(result.key_frames.size(), 10u);
  EXPECT_GE(result.refinements, 1);
  EXPECT_GT(result.points.size(), 300u);
  EXPECT_GE(result.window_adjustments, 1);
  const Metrics metrics =
      EvaluateTrajectory(ReadTumTrajectory(manifest.groundtruth_path), result.trajectory, {});
  ASSERT_TRUE(metrics.distance_error_pct);
  EXPECT_LT(*metrics.distance_error_pct, 1.0);
  EXPECT_LT(metrics.ate_rmse_m, 0.003);
  // Every wall point lies on the cylinder.
  for (const Eigen::Vector3d& point : result.points) {
    EXPECT_NEAR(point.head<2>().norm(), *manifest.inner_radius_m, 1e-9);
  }
}

TEST(SparseVo, MissingRadiusIsAnInputError) {
  DatasetManifest manifest = OpenDataset(ShortSteelRun());
  manifest.inner_radius_m.reset();
  const Camera camera = ReadCamera(manifest.camera_path);
  const std::string message =
      InputErrorMessage([&] { RunSparseVo(manifest, camera, SparseVoOptions{}); });
  EXPECT_NE(message.find("radius"), std::string::npos) << message;
}

}  // namespace
}  // namespace pipescope
