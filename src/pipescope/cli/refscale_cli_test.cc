// End-to-end tests of `pipescope refscale` (000 §3.3): simulate a target, measure it, write it.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <yaml-cpp/yaml.h>

#include <array>
#include <cstdio>
#include <string>

#include "pipescope/cli/cli_testing.h"
#include "pipescope/util/atomic_file.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

class RefscaleCli : public testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new std::filesystem::path(MakeTestDirectory("refscale_cli"));
    const CommandResult simulate =
        RunPipescope("simulate --preset scale-target --out " + (*dir_ / "ds").string() +
                     " --frames 1 --set width=512 --set height=384 --set white_card_count=1 -q");
    ASSERT_EQ(simulate.exit_status, 0) << simulate.output;
  }
  static void TearDownTestSuite() {
    std::filesystem::remove_all(*dir_);
    delete dir_;
  }
  static std::string Path(const std::string& name) { return (*dir_ / "ds" / name).string(); }

  static std::filesystem::path* dir_;
};

std::filesystem::path* RefscaleCli::dir_ = nullptr;

TEST_F(RefscaleCli, PrintsAndWritesTheScale) {
  const double truth =
      YAML::LoadFile(Path("dataset.yaml"))["reference_scale_px_per_m"].as<double>();
  // A user's manifest with a comment and a key pipescope does not know.
  const std::filesystem::path manifest = *dir_ / "user.yaml";
  WriteTextFileAtomically(manifest, "# pipe 1\nname: pipe1\nvendor: {id: 7}\n");
  const CommandResult run =
      RunPipescope("refscale " + Path("images/000000.png") + " --camera " + Path("camera.yaml") +
                   " --grid 5x4 --spacing-m 0.01 --write " + manifest.string());
  ASSERT_EQ(run.exit_status, 0) << run.output;
  EXPECT_NE(run.output.find("reference_scale_px_per_m: "), std::string::npos) << run.output;
  const std::string text = ReadTextFile(manifest);
  EXPECT_EQ(text.rfind("# pipe 1\nname: pipe1\nvendor: {id: 7}\nreference_scale_px_per_m: ", 0), 0u)
      << text;
  const YAML::Node written = YAML::Load(text);
  EXPECT_EQ(written["vendor"]["id"].as<int>(), 7);
  EXPECT_NEAR(written["reference_scale_px_per_m"].as<double>() / truth, 1.0, 0.002);
}

TEST_F(RefscaleCli, BadInputExitsTwoAndNamesTheCulprit) {
  const std::string camera = " --camera " + Path("camera.yaml");
  const std::string image = Path("images/000000.png");
  const struct {
    std::string arguments;
    std::string culprit;
  } cases[] = {
      {"refscale /nonexistent.png" + camera + " --grid 5x4 --spacing-m 0.01", "nonexistent.png"},
      {"refscale " + image + " --camera /nonexistent.yaml --grid 5x4 --spacing-m 0.01",
       "nonexistent.yaml"},
      {"refscale " + image + camera + " --grid 5by4 --spacing-m 0.01", "--grid"},
      {"refscale " + image + camera + " --grid 5x4 --spacing-m -1", "--spacing-m"},
      {"refscale " + image + camera + " --grid 5x4", "--spacing-m"},
      // No 6 x 4 grid in the image.
      {"refscale " + image + camera + " --grid 6x4 --spacing-m 0.01", "000000.png"},
      // A white card holds no circles.
      {"refscale " + Path("white_card/000000.png") + camera + " --grid 5x4 --spacing-m 0.01",
       "white_card"},
      {"refscale " + image + camera + " --grid 5x4 --spacing-m 0.01 --write /nonexistent.yaml",
       "--write"},
  };
  for (const auto& [arguments, culprit] : cases) {
    const CommandResult run = RunPipescope(arguments);
    EXPECT_EQ(run.exit_status, 2) << arguments << "\n" << run.output;
    EXPECT_NE(run.output.find(culprit), std::string::npos) << arguments << "\n" << run.output;
  }
  // An image of another size than the calibration.
  const std::filesystem::path other_camera = *dir_ / "other_camera.yaml";
  std::string calibration = ReadTextFile(Path("camera.yaml"));
  calibration.replace(calibration.find("width: 512"), 10, "width: 640");
  WriteTextFileAtomically(other_camera, calibration);
  const CommandResult mismatch = RunPipescope(
      "refscale " + image + " --camera " + other_camera.string() + " --grid 5x4 --spacing-m 0.01");
  EXPECT_EQ(mismatch.exit_status, 2) << mismatch.output;
  EXPECT_NE(mismatch.output.find("other_camera.yaml"), std::string::npos) << mismatch.output;
}

}  // namespace
}  // namespace pipescope
