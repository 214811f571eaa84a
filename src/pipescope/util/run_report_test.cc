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

}  // namespace
}  // namespace pipescope
