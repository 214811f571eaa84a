// End-to-end tests of `pipescope mosaic` (000 §6.1): simulate a short pass, stitch it at the
// ground-truth poses in both modes, and reject bad input naming the culprit.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <string>

#include "pipescope/cli/cli_testing.h"
#include "pipescope/util/atomic_file.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

class MosaicCli : public testing::Test {
 protected:
  // 16-inch steel pipe of 000 at 160x120: zeta = 80 / tan(12.5 deg) / 0.19378 m = 1863 px/m,
  // and 12 frames at 30 fps move 35 mm (about 65 px).
  static void SetUpTestSuite() {
    dir_ = new std::filesystem::path(MakeTestDirectory("mosaic_cli"));
    const CommandResult simulate =
        RunPipescope("simulate --preset steel-16in --out " + Path("ds") +
                     " --frames 12 --set width=160 --set height=120 --set white_card_count=1 -q");
    ASSERT_EQ(simulate.exit_status, 0) << simulate.output;
  }
  static void TearDownTestSuite() {
    std::filesystem::remove_all(*dir_);
    delete dir_;
  }
  static std::string Path(const std::string& name) { return (*dir_ / name).string(); }
  static std::string Dataset() {
    return Path("ds") + " --trajectory " + Path("ds/groundtruth.tum");
  }

  static std::filesystem::path* dir_;
};

std::filesystem::path* MosaicCli::dir_ = nullptr;

TEST_F(MosaicCli, UnrolledMosaicCoversTheFootprintOfThePass) {
  const CommandResult run = RunPipescope("mosaic " + Dataset() + " --out " + Path("unrolled.png"));
  ASSERT_EQ(run.exit_status, 0) << run.output;
  const cv::Mat mosaic = cv::imread(Path("unrolled.png"), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(mosaic.type(), CV_8U);
  // One cell per image pixel at the wall (1 / zeta): the image's 160 columns plus the travel
  // along h, and its 120 rows around the pipe (a little more: the wall curves away).
  EXPECT_GT(mosaic.cols, 160 + 50);
  EXPECT_LT(mosaic.cols, 160 + 80);
  EXPECT_GT(mosaic.rows, 115);
  EXPECT_LT(mosaic.rows, 140);
  EXPECT_GT(cv::countNonZero(mosaic), mosaic.total() * 8 / 10);

  // Coarser cells on request: 2 mm is about 3.7 image pixels.
  const CommandResult coarse =
      RunPipescope("mosaic " + Dataset() + " --pixel-mm 2 --out " + Path("coarse.png") + " -q");
  ASSERT_EQ(coarse.exit_status, 0) << coarse.output;
  const cv::Mat small = cv::imread(Path("coarse.png"), cv::IMREAD_UNCHANGED);
  EXPECT_NEAR(small.cols, mosaic.cols * 0.5369 / 2.0, 4);
}

TEST_F(MosaicCli, ImageMosaicPlacesFramesAtLeastFiftyPixelsApart) {
  const CommandResult run =
      RunPipescope("mosaic " + Dataset() + " --mode image --out " + Path("image.png") + " -q");
  ASSERT_EQ(run.exit_status, 0) << run.output;
  const cv::Mat mosaic = cv::imread(Path("image.png"), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(mosaic.type(), CV_8U);
  // Frame 0, then the first frame 50 px on (no later frame is another 50 px on): 160 + 50..65
  // columns, the height of a frame plus the lateral wander.
  EXPECT_GE(mosaic.cols, 160 + 50);
  EXPECT_LE(mosaic.cols, 160 + 66);
  EXPECT_GE(mosaic.rows, 120);
  EXPECT_LT(mosaic.rows, 130);
  EXPECT_GT(cv::countNonZero(mosaic), mosaic.total() * 8 / 10);
}

TEST_F(MosaicCli, BadInputExitsTwoAndNamesTheCulprit) {
  // A manifest without the reference scale, beside the simulated one.
  std::string manifest = ReadTextFile(Path("ds/dataset.yaml"));
  const std::size_t key = manifest.find("reference_scale_px_per_m");
  ASSERT_NE(key, std::string::npos);
  manifest.erase(key, manifest.find('\n', key) - key);
  WriteTextFileAtomically(Path("ds/no_scale.yaml"), manifest);
  // Poses an hour after the frames.
  WriteTextFileAtomically(Path("late.tum"), "3600 0 0 0 0 0 0 1\n");
  const std::string trajectory = " --trajectory " + Path("ds/groundtruth.tum");
  const struct {
    std::string arguments;
    std::string culprit;
  } cases[] = {
      {"mosaic " + Dataset() + " --out " + Path("m.png") + " --mode sideways", "--mode"},
      {"mosaic " + Path("ds") + " --trajectory /nonexistent.tum --out " + Path("m.png"),
       "nonexistent.tum"},
      {"mosaic " + Path("ds") + " --trajectory " + Path("late.tum") + " --out " + Path("m.png"),
       "--trajectory"},
      {"mosaic " + Dataset() + " --out " + Path("m.jpg"), "--out"},
      {"mosaic " + Dataset() + " --out " + Path("m.png") + " --pixel-mm 0", "--pixel-mm"},
      {"mosaic " + Path("ds/no_scale.yaml") + trajectory + " --mode image --out " + Path("m.png"),
       "reference_scale_px_per_m"},
      {"mosaic /nonexistent_dataset" + trajectory + " --out " + Path("m.png"),
       "nonexistent_dataset"},
  };
  for (const auto& [arguments, culprit] : cases) {
    const CommandResult run = RunPipescope(arguments);
    EXPECT_EQ(run.exit_status, 2) << arguments << "\n" << run.output;
    EXPECT_NE(run.output.find(culprit), std::string::npos) << arguments << "\n" << run.output;
  }
  EXPECT_FALSE(std::filesystem::exists(Path("m.png")));
}

}  // namespace
}  // namespace pipescope
