#include "pipescope/synthetic/dataset_writer.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "pipescope/camera/camera_io.h"
#include "pipescope/io/dataset.h"
#include "pipescope/io/image_source.h"
#include "pipescope/io/junctions.h"
#include "pipescope/io/trajectory.h"
#include "pipescope/synthetic/presets.h"
#include "pipescope/synthetic/scene_layouts.h"
#include "pipescope/util/atomic_file.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

SimulationConfig SmallConfig(const std::string& preset) {
  SimulationConfig config = PresetConfig(preset);
  config.width = 128;
  config.height = 96;
  config.frames = 4;
  config.white_card_count = 2;
  return config;
}

TEST(DatasetWriter, WritesAReadableDatasetWithGroundTruth) {
  const auto dir = MakeTestDirectory("simulate_files");
  const SimulationSummary summary = SimulateDataset(SmallConfig("steel-16in"), dir / "ds");
  EXPECT_EQ(summary.frames, 4);
  const DatasetManifest manifest = OpenDataset(dir / "ds");
  EXPECT_EQ(manifest.name, "steel-16in");
  EXPECT_NEAR(*manifest.inner_radius_m, 0.19378, 1e-12);
  ASSERT_TRUE(manifest.pipe_up.has_value());
  EXPECT_EQ(*manifest.pipe_up, Eigen::Vector3d(0.0, -1.0, 0.0));  // gravity is +Y (scene.h)
  ASSERT_TRUE(manifest.reference_scale_px_per_m.has_value());
  EXPECT_FALSE(manifest.gain_mask_path.empty());
  const Camera camera = ReadCamera(manifest.camera_path);
  auto source = ImageSource::Open(
      manifest, {.expected_width = camera.Width(), .expected_height = camera.Height()});
  int frames = 0;
  double total_mean = 0.0;
  while (std::optional<Frame> frame = source->Next()) {
    ++frames;
    total_mean += cv::mean(frame->grey)[0];
  }
  EXPECT_EQ(frames, 4);
  EXPECT_GT(total_mean / frames, 20.0);  // lit, not black
  const Trajectory truth = ReadTumTrajectory(manifest.groundtruth_path);
  ASSERT_EQ(truth.size(), 4u);
  EXPECT_NEAR(truth[1].timestamp, 1.0 / 30.0, 1e-9);
  const cv::Mat mask = cv::imread(manifest.gain_mask_path.string(), cv::IMREAD_ANYDEPTH);
  ASSERT_EQ(mask.type(), CV_16U);
  double max_value = 0.0;
  cv::minMaxLoc(mask, nullptr, &max_value);
  EXPECT_EQ(max_value, 65535.0);
  EXPECT_TRUE(std::filesystem::exists(dir / "ds" / "white_card" / "000001.png"));
  // No staging folder left behind.
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir),
                          std::filesystem::directory_iterator()),
            1);
}

TEST(DatasetWriter, SameSeedSameBytesOtherSeedOtherImages) {
  const auto dir = MakeTestDirectory("simulate_determinism");
  SimulationConfig config = SmallConfig("culvert");
  SimulateDataset(config, dir / "a");
  SimulateDataset(config, dir / "b");
  config.seed = 2;
  SimulateDataset(config, dir / "c");
  for (const char* file : {"images/000003.png", "groundtruth.tum", "gain_mask.png", "scene.yaml",
                           "camera.yaml", "dataset.yaml"}) {
    EXPECT_EQ(ReadTextFile(dir / "a" / file), ReadTextFile(dir / "b" / file)) << file;
  }
  EXPECT_NE(ReadTextFile(dir / "a" / "images/000003.png"),
            ReadTextFile(dir / "c" / "images/000003.png"));
}

TEST(DatasetWriter, NetworkSceneHasItsJunctions) {
  const auto dir = MakeTestDirectory("simulate_network");
  SimulateDataset(SmallConfig("fiberglass-network"), dir / "net");
  const std::vector<Junction> junctions = ReadSceneJunctions(dir / "net" / "scene.yaml");
  ASSERT_EQ(junctions.size(), 4u);
  double t1_t2 = 0.0;
  for (const Junction& a : junctions) {
    for (const Junction& b : junctions) {
      if (a.name == "T1" && b.name == "T2") t1_t2 = (a.center - b.center).norm();
    }
  }
  const std::vector<Eigen::Vector3d> corners = SquareLoopCorners(false);
  EXPECT_NEAR(t1_t2, (corners[1] - corners[0]).norm(), 1e-9);
  EXPECT_NEAR(t1_t2, 8.150, 0.03);  // 001 Table I
}

TEST(DatasetWriter, RefusesToReplaceAFolderThatIsNotADataset) {
  const auto dir = MakeTestDirectory("simulate_refuse");
  WriteTextFileAtomically(dir / "precious" / "notes.txt", "keep me");
  EXPECT_NE(InputErrorMessage([&] {
              SimulateDataset(SmallConfig("steel-6in"), dir / "precious");
            }).find("precious"),
            std::string::npos);
  EXPECT_EQ(ReadTextFile(dir / "precious" / "notes.txt"), "keep me");
  // An earlier simulated dataset is replaced.
  SimulateDataset(SmallConfig("steel-6in"), dir / "ds");
  SimulationConfig shorter = SmallConfig("steel-6in");
  shorter.frames = 2;
  SimulateDataset(shorter, dir / "ds");
  EXPECT_FALSE(std::filesystem::exists(dir / "ds" / "images" / "000003.png"));
  EXPECT_TRUE(std::filesystem::exists(dir / "ds" / "images" / "000001.png"));
}

}  // namespace
}  // namespace pipescope
