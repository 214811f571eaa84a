// End-to-end tests of `pipescope calibrate` (issue 4): simulate board views, calibrate, compare.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "pipescope/cli/cli_testing.h"
#include "pipescope/util/atomic_file.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

class CalibrateCli : public testing::Test {
 protected:
  // A small board dataset, and pipe images without a board at the same and at another size.
  static void SetUpTestSuite() {
    dir_ = new std::filesystem::path(MakeTestDirectory("calibrate_cli"));
    for (const std::string& arguments :
         {"--preset checkerboard --frames 10 --set width=480 --set height=360 --out " + Path("cb"),
          "--preset steel-16in --frames 1 --set width=480 --set height=360 "
          "--set white_card_count=1 --out " +
              Path("pipe"),
          "--preset steel-16in --frames 1 --set width=320 --set height=240 "
          "--set white_card_count=1 --out " +
              Path("small")}) {
      const CommandResult simulate = RunPipescope("simulate " + arguments + " -q");
      ASSERT_EQ(simulate.exit_status, 0) << simulate.output;
    }
  }
  static void TearDownTestSuite() {
    std::filesystem::remove_all(*dir_);
    delete dir_;
  }
  static std::string Path(const std::string& name) { return (*dir_ / name).string(); }

  static std::filesystem::path* dir_;
};

std::filesystem::path* CalibrateCli::dir_ = nullptr;

TEST_F(CalibrateCli, CalibratesAndListsImagesWithoutTheBoard) {
  const std::string pipe_image = Path("pipe/images/000000.png");
  const CommandResult result =
      RunPipescope("calibrate --model pinhole-radtan --board 9x6 --square-m 0.025 " +
                   Path("cb/images") + " " + pipe_image + " --out " + Path("out/camera.yaml"));
  ASSERT_EQ(result.exit_status, 0) << result.output;
  EXPECT_NE(result.output.find("no 9x6 board found in 1 of 11 images"), std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find(pipe_image), std::string::npos);
  EXPECT_NE(result.output.find("rms_px"), std::string::npos);  // the per-image table

  const YAML::Node truth = YAML::LoadFile(Path("cb/camera.yaml"));
  const YAML::Node fitted = YAML::LoadFile(Path("out/camera.yaml"));
  EXPECT_EQ(fitted["model"].as<std::string>(), "pinhole-radtan");
  EXPECT_EQ(fitted["width"].as<int>(), 480);
  const double true_fx = truth["params"][0].as<double>();
  // Ten views of a 480x360 image: looser than the 0.2 % of the 20-view library test.
  EXPECT_NEAR(fitted["params"][0].as<double>(), true_fx, 0.005 * true_fx);
  EXPECT_NEAR(fitted["params"][2].as<double>(), truth["params"][2].as<double>(), 1.0);

  const nlohmann::json report = nlohmann::json::parse(ReadTextFile(Path("out/calibration.json")));
  EXPECT_EQ(report["views"].size(), 10u);
  EXPECT_EQ(report["images_without_board"], nlohmann::json::array({pipe_image}));
  EXPECT_LT(report["rms_px"].get<double>(), 0.1);
  EXPECT_EQ(report["board"]["cols"], 9);
}

TEST_F(CalibrateCli, NoBoardAnywhereExitsTwo) {
  const CommandResult result =
      RunPipescope("calibrate --model fisheye-poly --board 9x6 --square-m 0.025 " +
                   Path("pipe/images") + " --out " + Path("none/camera.yaml"));
  EXPECT_EQ(result.exit_status, 2) << result.output;
  EXPECT_NE(result.output.find("no 9x6 checkerboard found in any of the 1 images"),
            std::string::npos)
      << result.output;
  EXPECT_FALSE(std::filesystem::exists(Path("none/camera.yaml")));
}

TEST_F(CalibrateCli, ImagesOfDifferentSizesExitTwo) {
  const std::string small = Path("small/images/000000.png");
  const CommandResult result =
      RunPipescope("calibrate --model kannala-brandt --board 9x6 --square-m 0.025 " +
                   Path("cb/images") + " " + small + " --out " + Path("sizes/camera.yaml"));
  EXPECT_EQ(result.exit_status, 2) << result.output;
  EXPECT_NE(result.output.find(small + " is 320x240"), std::string::npos) << result.output;
}

TEST_F(CalibrateCli, BadFlagsExitTwoAndNameTheFlag) {
  const std::string images = Path("cb/images");
  const CommandResult board =
      RunPipescope("calibrate --model pinhole-radtan --board 9by6 " +
                   std::string("--square-m 0.025 ") + images + " --out " + Path("bad/camera.yaml"));
  EXPECT_EQ(board.exit_status, 2);
  EXPECT_NE(board.output.find("--board"), std::string::npos) << board.output;
  const CommandResult model = RunPipescope(
      "calibrate --model fisheye --board 9x6 --square-m "
      "0.025 " +
      images + " --out " + Path("bad/camera.yaml"));
  EXPECT_EQ(model.exit_status, 2);
  EXPECT_NE(model.output.find("--model"), std::string::npos) << model.output;
  const CommandResult missing =
      RunPipescope("calibrate --model fisheye-poly --board 9x6 --square-m 0.025 " +
                   Path("nowhere") + " --out " + Path("bad/camera.yaml"));
  EXPECT_EQ(missing.exit_status, 2);
  EXPECT_NE(missing.output.find(Path("nowhere")), std::string::npos) << missing.output;
}

}  // namespace
}  // namespace pipescope
