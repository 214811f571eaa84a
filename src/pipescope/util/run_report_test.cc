#include "pipescope/util/run_report.h"

#include <gtest/gtest.h>

namespace pipescope {
namespace {

TEST(RunReport, CollectsCountsTimingsAndWarnings) {
  RunReport report("odometry");
  report.SetMethod("dense-lk");
  report.IncrementCount("frames_skipped");
  report.IncrementCount("frames_skipped");
  report.AddTiming("total", 1.5);
  report.AddTiming("total", 0.5);
  report.Warn("frame 7 unreadable");
  const nlohmann::json json = report.ToJson();
  EXPECT_EQ(json["command"], "odometry");
  EXPECT_EQ(json["method"], "dense-lk");
  EXPECT_EQ(json["counts"]["frames_skipped"], 2);
  EXPECT_DOUBLE_EQ(json["timings_s"]["total"].get<double>(), 2.0);
  ASSERT_EQ(json["warnings"].size(), 1u);
  EXPECT_EQ(json["version"], PipescopeVersion());
  EXPECT_EQ(report.Count("frames_skipped"), 2);
  EXPECT_EQ(report.Count("absent"), 0);
}

TEST(RunReport, StageTimesGoInAsWallAndCpuTimings) {
  StageTimes reader;  // another thread's stages, merged
  reader.Add("read", 0.25, 0.125);
  StageTimes times;
  times.Add("read", 0.5, 0.25);
  times.Merge(reader);
  times.AddWall("wait", 2.0);
  const StageClock<> clock;
  clock.AddTo(&times, "timed");
  clock.AddTo(nullptr, "nowhere");  // no StageTimes: nothing happens
  RunReport report("map");
  report.AddStageTimes("odometry", times);
  report.AddStageTimes("", times);
  const nlohmann::json json = report.ToJson();
  const nlohmann::json& timings = json.at("timings_s");
  EXPECT_FALSE(timings.contains("_read"));
  EXPECT_DOUBLE_EQ(timings["odometry_read"].get<double>(), 0.75);
  EXPECT_DOUBLE_EQ(timings["odometry_read_cpu"].get<double>(), 0.375);
  EXPECT_DOUBLE_EQ(timings["read"].get<double>(), 0.75);
  EXPECT_DOUBLE_EQ(timings["wait"].get<double>(), 2.0);
  EXPECT_FALSE(timings.contains("wait_cpu"));  // waiting has no CPU time to report
  EXPECT_TRUE(timings.contains("odometry_timed_cpu"));
  EXPECT_GE(timings["odometry_timed"].get<double>(), 0.0);
}

}  // namespace
}  // namespace pipescope
