// End-to-end tests of the `pipescope` program: exit statuses, messages and written files.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>

#include "pipescope/util/atomic_file.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

struct CommandResult {
  int exit_status = -1;
  std::string output;  // stdout and stderr together
};

CommandResult RunPipescope(const std::string& arguments) {
  const std::string command = std::string(PIPESCOPE_BINARY) + " " + arguments + " 2>&1";
  CommandResult result;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return result;
  std::array<char, 4096> buffer;
  while (fgets(buffer.data(), buffer.size(), pipe) != nullptr) result.output += buffer.data();
  const int status = pclose(pipe);
  result.exit_status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

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

}  // namespace
}  // namespace pipescope
