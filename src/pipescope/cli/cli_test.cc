// End-to-end tests of the `pipescope` program: exit statuses, messages and written files.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>

#include "pipescope/cli/cli_testing.h"
#include "pipescope/util/atomic_file.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

const std::string kDemo = std::string(PIPESCOPE_TEST_DATA_DIR) + "/demo/";

TEST(Cli, HelpOnEveryLevelExitsZero) {
  const CommandResult top = RunPipescope("--help");
  EXPECT_EQ(top.exit_status, 0);
  EXPECT_NE(top.output.find("evaluate"), std::string::npos);
  const CommandResult evaluate = RunPipescope("evaluate --help");
  EXPECT_EQ(evaluate.exit_status, 0);
  EXPECT_NE(evaluate.output.find("--align"), std::string::npos);
}

TEST(Cli, EvaluateDemoPairWritesMetrics) {
  const auto dir = MakeTestDirectory("cli_evaluate");
  const std::string json_path = (dir / "metrics.json").string();
  const CommandResult result = RunPipescope("evaluate --gt " + kDemo + "groundtruth.tum --est " +
                                            kDemo + "estimate.tum --json " + json_path + " -q");
  ASSERT_EQ(result.exit_status, 0) << result.output;
  const nlohmann::json metrics = nlohmann::json::parse(ReadTextFile(json_path));
  // The demo estimate lags 2 ms, well inside the 10 ms association tolerance.
  EXPECT_EQ(metrics["frames_gt"], 401);
  EXPECT_EQ(metrics["frames_matched"], 401);
  // Out and back, 2 m each way; the estimate's legs are 0.3 % long and 0.2 % short, plus a
  // random walk of 0.2 mm a frame (about 3 mm a leg, 0.15 %), so the leg errors lie near those.
  EXPECT_NEAR(metrics["distance_gt_m"].get<double>(), 4.0, 0.01);
  EXPECT_NEAR(metrics["forward_error_pct"].get<double>(), 0.3, 0.3);
  EXPECT_NEAR(metrics["reverse_error_pct"].get<double>(), 0.2, 0.3);
  EXPECT_TRUE(metrics["junction_distances"].is_null());
  EXPECT_EQ(metrics["alignment"], "se3");
  EXPECT_TRUE(metrics.contains("ate_rmse_m"));
  EXPECT_TRUE(metrics.contains("rpe_1m_pct"));
}

TEST(Cli, BadInputExitsTwoAndNamesTheCulprit) {
  const CommandResult missing =
      RunPipescope("evaluate --gt /nonexistent/gt.tum --est " + kDemo + "estimate.tum");
  EXPECT_EQ(missing.exit_status, 2);
  EXPECT_NE(missing.output.find("--gt"), std::string::npos) << missing.output;

  const CommandResult bad_align = RunPipescope("evaluate --gt " + kDemo + "groundtruth.tum --est " +
                                               kDemo + "estimate.tum --align affine");
  EXPECT_EQ(bad_align.exit_status, 2);
  EXPECT_NE(bad_align.output.find("--align"), std::string::npos) << bad_align.output;

  const auto dir = MakeTestDirectory("cli_bad_tum");
  WriteTextFileAtomically(dir / "bad.tum", "0 0 0 0 0 0 0 1\n1 0 0 oops 0 0 0 1\n");
  const CommandResult malformed =
      RunPipescope("evaluate --gt " + kDemo + "groundtruth.tum --est " +
                   (dir / "bad.tum").string() + " --json " + (dir / "m.json").string());
  EXPECT_EQ(malformed.exit_status, 2);
  EXPECT_NE(malformed.output.find("bad.tum"), std::string::npos) << malformed.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "m.json"));

  EXPECT_EQ(RunPipescope("no-such-command").exit_status, 2);
  EXPECT_EQ(RunPipescope("").exit_status, 2);
}

TEST(Cli, SimulateListsPresetsAndRejectsBadKeys) {
  const CommandResult list = RunPipescope("simulate --list-presets");
  EXPECT_EQ(list.exit_status, 0);
  for (const char* expected :
       {"steel-6in", "fiberglass-network", "texture_contrast", "noise_sigma"}) {
    EXPECT_NE(list.output.find(expected), std::string::npos) << expected;
  }
  const auto dir = MakeTestDirectory("cli_simulate_bad");
  const std::string out = " --out " + (dir / "ds").string();
  const CommandResult unknown_key =
      RunPipescope("simulate --preset culvert --set colour=red" + out);
  EXPECT_EQ(unknown_key.exit_status, 2);
  EXPECT_NE(unknown_key.output.find("colour"), std::string::npos) << unknown_key.output;
  const CommandResult bad_value = RunPipescope("simulate --preset culvert --set fps=-3" + out);
  EXPECT_EQ(bad_value.exit_status, 2);
  EXPECT_NE(bad_value.output.find("fps"), std::string::npos) << bad_value.output;
  const CommandResult bad_preset = RunPipescope("simulate --preset sewer" + out);
  EXPECT_EQ(bad_preset.exit_status, 2);
  EXPECT_NE(bad_preset.output.find("--preset"), std::string::npos) << bad_preset.output;
  EXPECT_EQ(RunPipescope("simulate --preset culvert").exit_status, 2);  // no --out
  EXPECT_FALSE(std::filesystem::exists(dir / "ds"));
}

TEST(Cli, SimulateSaysWhenThePresetsFramesStopShortOfTheRoute) {
  // Route B (42.6 m) is longer than route A, whose 26 000 frames are the preset's: at the
  // preset's speed they end before the second pass of T1-T4. Tiny frames keep this quick.
  const auto dir = MakeTestDirectory("cli_simulate_route");
  const std::string tiny = " --set width=64 --set height=48 -q --out ";
  const CommandResult short_b = RunPipescope("simulate --preset fiberglass-network --set route=B" +
                                             tiny + (dir / "b").string());
  ASSERT_EQ(short_b.exit_status, 0) << short_b.output;
  EXPECT_NE(short_b.output.find("m before the end of the route"), std::string::npos)
      << short_b.output;
  EXPECT_NE(short_b.output.find("--frames 34"), std::string::npos) << short_b.output;
  // Route A's own frames reach its end; a frame count the user gave is a cut, and a preset whose
  // frames stop short by design (culvert) is as its preset says: neither is warned of.
  const CommandResult whole_a =
      RunPipescope("simulate --preset fiberglass-network" + tiny + (dir / "a").string());
  ASSERT_EQ(whole_a.exit_status, 0) << whole_a.output;
  EXPECT_EQ(whole_a.output.find("before the end of the route"), std::string::npos)
      << whole_a.output;
  const CommandResult cut = RunPipescope(
      "simulate --preset fiberglass-network --set route=B --frames 20" + tiny + (dir / "cut").string());
  ASSERT_EQ(cut.exit_status, 0) << cut.output;
  EXPECT_EQ(cut.output.find("before the end of the route"), std::string::npos) << cut.output;
  const CommandResult culvert =
      RunPipescope("simulate --preset culvert" + tiny + (dir / "culvert").string());
  ASSERT_EQ(culvert.exit_status, 0) << culvert.output;
  EXPECT_EQ(culvert.output.find("before the end of the route"), std::string::npos)
      << culvert.output;
}

TEST(Cli, SimulateThenGainmaskAndUndistort) {
  const auto dir = MakeTestDirectory("cli_simulate");
  const std::string ds = (dir / "ds").string();
  const CommandResult simulate = RunPipescope(
      "simulate --preset steel-16in --frames 3 --set width=160 --set height=120 -q --out " + ds +
      "/");  // a trailing slash is fine
  ASSERT_EQ(simulate.exit_status, 0) << simulate.output;
  EXPECT_TRUE(std::filesystem::exists(dir / "ds" / "images" / "000002.png"));
  const CommandResult mask =
      RunPipescope("gainmask " + ds + "/white_card --out " + (dir / "mask.png").string() + " -q");
  ASSERT_EQ(mask.exit_status, 0) << mask.output;
  const CommandResult rectified =
      RunPipescope("undistort " + ds + " --out " + (dir / "rect").string() + " -q");
  ASSERT_EQ(rectified.exit_status, 0) << rectified.output;
  EXPECT_TRUE(std::filesystem::exists(dir / "rect" / "images" / "000002.png"));
  EXPECT_TRUE(std::filesystem::exists(dir / "rect" / "dataset.yaml"));
  EXPECT_EQ(RunPipescope("gainmask " + (dir / "none").string() + " --out x.png").exit_status, 2);
}

}  // namespace
}  // namespace pipescope
