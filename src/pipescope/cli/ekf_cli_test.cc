// End-to-end test of `pipescope odometry --method ekf` (004): a short pass through the start of
// the tube-bend preset gives the run directory the issue lists (trajectory, sections in
// run.json, centreline CSV and PLY, dewarped mosaic, metrics), in agreement with each other.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <string>

#include "pipescope/cli/cli_testing.h"
#include "pipescope/util/atomic_file.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

class EkfCli : public testing::Test {
 protected:
  // 004's set-up at 320x240: 90 frames, 0.3 m of the first straight.
  static void SetUpTestSuite() {
    dir_ = new std::filesystem::path(MakeTestDirectory("ekf_cli"));
    const CommandResult simulate =
        RunPipescope("simulate --preset tube-bend --out " + Path("ds") +
                     " --frames 90 --set width=320 --set height=240 --set white_card_count=2 -q");
    ASSERT_EQ(simulate.exit_status, 0) << simulate.output;
  }
  static void TearDownTestSuite() {
    std::filesystem::remove_all(*dir_);
    delete dir_;
  }
  static std::string Path(const std::string& name) { return (*dir_ / name).string(); }

  static std::filesystem::path* dir_;
};

std::filesystem::path* EkfCli::dir_ = nullptr;

TEST_F(EkfCli, WritesSectionsCentrelineAndMosaic) {
  const std::string run = Path("run");
  const CommandResult result =
      RunPipescope("odometry " + Path("ds") + " --method ekf --out " + run + " -q");
  ASSERT_EQ(result.exit_status, 0) << result.output;
  const nlohmann::json metrics = nlohmann::json::parse(ReadTextFile(run + "/metrics.json"));
  EXPECT_EQ(metrics["frames_est"], 90);
  // 0.3 m with the preset's hand-held wobble (the accuracy figures are in docs/ekf.md).
  EXPECT_LT(metrics["distance_error_pct"].get<double>(), 3.0);
  const nlohmann::json report = nlohmann::json::parse(ReadTextFile(run + "/run.json"));
  EXPECT_EQ(report["method"], "ekf");
  // Looking down the tube "by the view" comes to bending sections, one radius of look-ahead and
  // a flat field of 0.1 rad: 16 px at the 320 x 240 pinhole camera's 160 px a radian.
  EXPECT_DOUBLE_EQ(report["chosen_by_the_view"]["curvature_sigma_radii"].get<double>(), 0.3);
  EXPECT_DOUBLE_EQ(report["chosen_by_the_view"]["spawn_lookahead_radii"].get<double>(), 1.0);
  EXPECT_NEAR(report["chosen_by_the_view"]["flat_field_sigma_px"].get<double>(), 16.0, 1e-6);
  ASSERT_GE(report["sections"].size(), 1u);
  const nlohmann::json& first = report["sections"][0];
  // The run's frame is the first section's: Z along its axis.
  EXPECT_NEAR(first["axis"][2].get<double>(), 1.0, 1e-9);
  EXPECT_NEAR(first["radius_m"].get<double>(), 0.1, 0.005);
  EXPECT_GT(report["innovation"]["updated_frames"].get<int>(), 80);
  EXPECT_EQ(report["quality"]["verdict"], "reliable");
  // A straight run has no bend to warn of.
  EXPECT_EQ(report.dump().find("the sections turn"), std::string::npos);

  // centreline.csv: a header and one line a vertex, arc lengths increasing to run.json's length.
  std::istringstream csv(ReadTextFile(run + "/centreline.csv"));
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "arc_m,x_m,y_m,z_m,radius_m,section");
  double last_arc = -1.0;
  int vertices = 0;
  while (std::getline(csv, line)) {
    const double arc = std::stod(line.substr(0, line.find(',')));
    EXPECT_GT(arc, last_arc);
    last_arc = arc;
    ++vertices;
  }
  EXPECT_GE(vertices, 2);
  EXPECT_NEAR(last_arc, report["centreline_length_m"].get<double>(), 1e-6);
  const std::string ply = ReadTextFile(run + "/centreline.ply");
  EXPECT_NE(ply.find("element vertex " + std::to_string(vertices)), std::string::npos);
  EXPECT_NE(ply.find("element edge " + std::to_string(vertices - 1)), std::string::npos);

  EXPECT_EQ(report["mosaic"]["kind"], "tube-unrolled");
  // A hundredth of the (estimated) radius.
  EXPECT_NEAR(report["mosaic"]["pixel_m"].get<double>(), 0.001, 2e-5);
  const cv::Mat mosaic = cv::imread(run + "/mosaic.png", cv::IMREAD_UNCHANGED);
  ASSERT_FALSE(mosaic.empty());
  // Rows around the tube: 2 pi r at a hundredth of the radius a cell.
  EXPECT_NEAR(mosaic.rows, 2.0 * M_PI * 100.0, 2.0);
  EXPECT_TRUE(std::filesystem::exists(run + "/stations.csv"));
  const std::string page = ReadTextFile(run + "/report.html");
  EXPECT_NE(page.find("Dewarped tube (along the centreline)"), std::string::npos);
}

// Through a 60-degree bend (legs of 0.35 m, 250 frames at 320x240): the sections turn with it, and
// the run calls its positions unconfirmed, since the filter cannot check the angle it turned,
// while its distances along the centreline keep their own verdict.
TEST_F(EkfCli, ARunThroughABendLeavesItsPositionsUnconfirmed) {
  const CommandResult simulate =
      RunPipescope("simulate --preset tube-bend --out " + Path("bend") +
                   " --frames 250 --set width=320 --set height=240 --set white_card_count=2"
                   " --set length_m=0.35 --set bend_angle_deg=60 -q");
  ASSERT_EQ(simulate.exit_status, 0) << simulate.output;
  const std::string run = Path("run-bend");
  const CommandResult result =
      RunPipescope("odometry " + Path("bend") + " --method ekf --out " + run + " -q --no-report");
  ASSERT_EQ(result.exit_status, 0) << result.output;
  const nlohmann::json report = nlohmann::json::parse(ReadTextFile(run + "/run.json"));
  const nlohmann::json& sections = report["sections"];
  ASSERT_GE(sections.size(), 2u);
  Eigen::Vector3d first, last;
  for (int k = 0; k < 3; ++k) {
    first[k] = sections.front()["axis"][k].get<double>();
    last[k] = sections.back()["end_axis"][k].get<double>();
  }
  // Measured: 76.1 degrees (the truth 60). With the bend in view from the first frame, the first
  // section bends over the 0.2 m of straight before it as well, which tilts its start, the run's
  // reference (docs/ekf.md, "What is not reached"); 66.0 with straight sections only. The
  // camera's own track holds better: ATE 3.8 mm and 1.5 degrees against 7.9 mm and 6.8.
  const double turn_deg = std::acos(first.normalized().dot(last.normalized())) * 180.0 / M_PI;
  EXPECT_NEAR(turn_deg, 60.0, 20.0);
  const nlohmann::json& quality = report["quality"];
  ASSERT_EQ(quality["position_reasons"].size(), 1u) << quality;
  EXPECT_NE(quality["position_reasons"][0].get<std::string>().find("the sections turn"),
            std::string::npos);
  EXPECT_EQ(quality["verdict"], "unreliable");
  // Nothing else went wrong on this clean rendering: the distance along the centreline stands.
  EXPECT_EQ(quality["along_pipe_verdict"], "reliable") << quality["reasons"];
}

TEST_F(EkfCli, BadConfigExitsTwoAndNamesTheKey) {
  WriteTextFileAtomically(*dir_ / "bad.yaml", "axis_along_tube: w\n");
  const CommandResult result = RunPipescope("odometry " + Path("ds") + " --method ekf --out " +
                                            Path("bad-run") + " --config " + Path("bad.yaml"));
  EXPECT_EQ(result.exit_status, 2);
  EXPECT_NE(result.output.find("axis_along_tube"), std::string::npos) << result.output;
  EXPECT_FALSE(std::filesystem::exists(Path("bad-run")));
}

}  // namespace
}  // namespace pipescope
