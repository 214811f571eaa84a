// `--list-keys` and `--config` of `odometry` and `map`: every key listed with its default, and a
// config file with an unknown key or a value out of range exits 2 naming the file and the key,
// before any run directory is written.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "pipescope/cli/cli_testing.h"
#include "pipescope/util/atomic_file.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

TEST(OptionsCli, ListKeysPrintsEveryKeyWithItsDefault) {
  const CommandResult odometry = RunPipescope("odometry --list-keys");
  ASSERT_EQ(odometry.exit_status, 0) << odometry.output;
  // A dense key with its default and range, a sparse one, with their units.
  EXPECT_NE(odometry.output.find("max_departure_from_prediction_px"), std::string::npos);
  EXPECT_NE(odometry.output.find("16 px"), std::string::npos) << odometry.output;
  EXPECT_NE(odometry.output.find("cross_section_anchor_sigma_m"), std::string::npos);
  EXPECT_NE(odometry.output.find("[0, 0.45]"), std::string::npos);
  const CommandResult map = RunPipescope("map --list-keys");
  ASSERT_EQ(map.exit_status, 0) << map.output;
  EXPECT_NE(map.output.find("window_interval"), std::string::npos);
  EXPECT_NE(map.output.find("tau"), std::string::npos);
}

TEST(OptionsCli, ABadConfigNamesTheFileAndTheKeyAndWritesNothing) {
  const std::filesystem::path dir = MakeTestDirectory("options_cli");
  const CommandResult simulate =
      RunPipescope("simulate --preset steel-16in --out " + (dir / "ds").string() +
                   " --frames 3 --set width=160 --set height=120 --set white_card_count=1 -q");
  ASSERT_EQ(simulate.exit_status, 0) << simulate.output;
  struct Case {
    std::string command;  // before the dataset
    std::string config;
    std::string key;
  };
  const Case cases[] = {
      {"odometry --method dense-lk", "downsample: 2\nno_such_key: 1\n", "no_such_key"},
      {"odometry --method phase", "key_frame_shift_fraction: 0.9\n", "key_frame_shift_fraction"},
      {"odometry --method sparse", "per_cell: -1\n", "per_cell"},
      {"odometry --method sparse", "axis_along_pipe: z\n", "axis_along_pipe"},
      {"map", "stages: 0\n", "stages"},
      {"map", "min_zncc: 5\n", "min_zncc"},
      {"map", "window_size: many\n", "window_size"},
  };
  int n = 0;
  for (const Case& c : cases) {
    const std::filesystem::path config = dir / ("config" + std::to_string(n) + ".yaml");
    const std::filesystem::path run = dir / ("run" + std::to_string(n++));
    WriteTextFileAtomically(config, c.config);
    const CommandResult result =
        RunPipescope(c.command + " " + (dir / "ds").string() + " --radius 0.2 --config " +
                     config.string() + " --out " + run.string() + " -q");
    EXPECT_EQ(result.exit_status, 2) << c.command << ": " << result.output;
    EXPECT_NE(result.output.find(config.string()), std::string::npos) << result.output;
    EXPECT_NE(result.output.find("'" + c.key + "'"), std::string::npos) << result.output;
    EXPECT_FALSE(std::filesystem::exists(run)) << c.command;
  }
}

}  // namespace
}  // namespace pipescope
