// RunDirectory writes a whole run or nothing: the target shows the old run until Commit(), and
// the files the GUIDE names, read back, hold what was written.
#include "pipescope/report/run_directory.h"

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

Trajectory StraightRun(int frames, double step_m) {
  Trajectory trajectory;
  for (int k = 0; k < frames; ++k) {
    StampedPose pose;
    pose.timestamp = 0.1 * k;
    pose.position = Eigen::Vector3d(0.0, 0.0, step_m * k);
    trajectory.push_back(pose);
  }
  return trajectory;
}

nlohmann::json ReadJson(const std::filesystem::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

TEST(RunDirectory, CommitPutsTheWholeRunInPlace) {
  const std::filesystem::path out = MakeTestDirectory("run_directory") / "run";
  RunDirectory run(out, "odometry", "dense-lk");
  run.report().SetCount("frames", 11);
  run.WriteTrajectory(StraightRun(11, 0.01));
  run.WriteKeyFrames(StraightRun(3, 0.05));
  run.WriteSparsePoints({Eigen::Vector3d(0.1, 0.0, 0.2)});
  cv::Mat mosaic(4, 6, CV_32F, cv::Scalar(0.5f));
  mosaic.at<float>(0, 0) = 1.0f;
  run.WriteMosaic(mosaic, "unrolled", 0.001, cv::Point2d(0.2, -0.1));
  // The estimate 1 % long against ground truth.
  const Metrics metrics =
      *run.WriteMetrics(StraightRun(11, 0.01), StraightRun(11, 0.0101), "gt.tum");
  ASSERT_TRUE(metrics.distance_error_pct.has_value());
  EXPECT_NEAR(*metrics.distance_error_pct, 1.0, 1e-9);
  EXPECT_FALSE(std::filesystem::exists(out)) << "nothing in place before Commit()";
  run.Commit();
  for (const char* name : {"trajectory.tum", "keyframes.tum", "points_sparse.ply", "mosaic.png",
                           "metrics.json", "run.json"}) {
    EXPECT_TRUE(std::filesystem::is_regular_file(out / name)) << name;
  }
  EXPECT_EQ(ReadTumTrajectory(out / "trajectory.tum").size(), 11u);
  const nlohmann::json report = ReadJson(out / "run.json");
  EXPECT_EQ(report["command"], "odometry");
  EXPECT_EQ(report["method"], "dense-lk");
  EXPECT_EQ(report["counts"]["frames"], 11);
  EXPECT_EQ(report["mosaic"]["width_px"], 6);
  EXPECT_DOUBLE_EQ(report["mosaic"]["pixel_m"].get<double>(), 0.001);
  EXPECT_TRUE(report["timings_s"].contains("total"));
  EXPECT_NEAR(ReadJson(out / "metrics.json")["distance_error_pct"].get<double>(), 1.0, 1e-9);
}

// A position reason (a map run's unconfirmed turn) makes the run unreliable and says so, while
// the distances along the pipe keep their own verdict; any other reason takes that too.
TEST(RunDirectory, PositionReasonsLeaveTheDistancesAlongThePipeStanding) {
  const std::filesystem::path out = MakeTestDirectory("run_directory_positions") / "run";
  const std::vector<FrameState> measured(20, FrameState::kMeasured);
  {
    RunDirectory run(out, "map", "fisheye");
    const RunQuality quality = run.SetQuality(measured, {}, {}, {"the turn at J1"});
    EXPECT_FALSE(quality.reliable);
    EXPECT_TRUE(quality.AlongPipeReliable());
    const std::string summary = RunQualitySummary(quality);
    EXPECT_NE(summary.find("UNRELIABLE positions: the turn at J1"), std::string::npos) << summary;
    EXPECT_NE(summary.find("distances along the pipe are reliable"), std::string::npos) << summary;
    run.Commit();
    const nlohmann::json quality_json = ReadJson(out / "run.json")["quality"];
    EXPECT_EQ(quality_json["verdict"], "unreliable");
    EXPECT_EQ(quality_json["along_pipe_verdict"], "reliable");
    EXPECT_EQ(quality_json["reasons"], nlohmann::json::array({"the turn at J1"}));
    EXPECT_EQ(quality_json["position_reasons"], nlohmann::json::array({"the turn at J1"}));
  }
  RunDirectory run(out, "map", "fisheye");
  const RunQuality quality = run.SetQuality(measured, {"windows rejected"}, {}, {"the turn at J1"});
  EXPECT_FALSE(quality.AlongPipeReliable());
  EXPECT_EQ(quality.reasons.size(), 2u);
  EXPECT_NE(RunQualitySummary(quality).find("do not trust this run's distances"),
            std::string::npos);
}

TEST(RunDirectory, ARunThatFailsLeavesTheOldOneWhole) {
  const std::filesystem::path out = MakeTestDirectory("run_directory_failed") / "run";
  {
    RunDirectory first(out, "odometry", "phase");
    first.WriteTrajectory(StraightRun(5, 0.01));
    first.Commit();
  }
  try {
    RunDirectory second(out, "odometry", "phase");
    second.WriteTrajectory(StraightRun(7, 0.01));
    throw std::runtime_error("the estimator failed");
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(ReadTumTrajectory(out / "trajectory.tum").size(), 5u);
  // No staging folder is left beside it.
  int entries = 0;
  for (const auto& entry : std::filesystem::directory_iterator(out.parent_path())) {
    (void)entry;
    ++entries;
  }
  EXPECT_EQ(entries, 1);
}

TEST(RunDirectory, RefusesAFolderThatIsNotARun) {
  const std::filesystem::path out = MakeTestDirectory("run_directory_foreign");
  std::ofstream(out / "notes.txt") << "mine\n";
  const std::string message =
      InputErrorMessage([&] { RunDirectory run(out, "map", "fisheye-sba-cylinder"); });
  EXPECT_NE(message.find("--out"), std::string::npos) << message;
  EXPECT_TRUE(std::filesystem::exists(out / "notes.txt"));
}

}  // namespace
}  // namespace pipescope
