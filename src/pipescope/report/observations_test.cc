#include "pipescope/report/observations.h"

#include <gtest/gtest.h>

#include "pipescope/util/atomic_file.h"
#include "pipescope/util/error.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

TEST(Observations, ReadsPointsAndBoxesByColumnName) {
  const auto dir = MakeTestDirectory("observations_read");
  WriteTextFileAtomically(dir / "points.csv",
                          "remark,frame,v,u,code\n\"crack, 3 cm\",12,240.5,320,CR\n");
  const std::vector<Observation> points = ReadObservationsCsv(dir / "points.csv");
  ASSERT_EQ(points.size(), 1u);
  EXPECT_EQ(points[0].frame, 12);
  EXPECT_FALSE(points[0].box);
  EXPECT_DOUBLE_EQ(points[0].u(), 320.0);
  EXPECT_DOUBLE_EQ(points[0].v(), 240.5);
  EXPECT_EQ(points[0].remark, "crack, 3 cm");
  WriteTextFileAtomically(dir / "boxes.csv", "frame,u_min,v_min,u_max,v_max\n3,10,20,30,60\n");
  const std::vector<Observation> boxes = ReadObservationsCsv(dir / "boxes.csv");
  ASSERT_EQ(boxes.size(), 1u);
  EXPECT_TRUE(boxes[0].box);
  EXPECT_DOUBLE_EQ(boxes[0].u(), 20.0);
  EXPECT_DOUBLE_EQ(boxes[0].v(), 40.0);
}

TEST(Observations, ErrorsNameTheFileLineAndColumn) {
  const auto dir = MakeTestDirectory("observations_bad");
  const std::pair<const char*, const char*> cases[] = {
      {"frame,u\n1,2\n", "no column 'v'"},
      {"frame,u,v\n1,2,x\n", ":2: column 'v'"},
      {"frame,u,v\n-1,2,3\n", "column 'frame'"},
      {"frame,u,v\n1,2\n", "2 fields, the header has 3"},
      {"frame,u_min,v_min,u_max,v_max\n1,5,5,4,9\n", "u_max"},
      {"", "empty file"}};
  for (const auto& [text, needle] : cases) {
    WriteTextFileAtomically(dir / "obs.csv", text);
    const std::string message = InputErrorMessage([&] { ReadObservationsCsv(dir / "obs.csv"); });
    EXPECT_NE(message.find("obs.csv"), std::string::npos) << message;
    EXPECT_NE(message.find(needle), std::string::npos) << message;
  }
}

TEST(Observations, LocatedFileRoundTrips) {
  LocatedObservation located;
  located.observation = {.frame = 7,
                         .box = true,
                         .u_min = 1,
                         .v_min = 2,
                         .u_max = 5,
                         .v_max = 8,
                         .code = "DEF",
                         .remark = "say \"hi\", twice"};
  located.located = true;
  located.centre.distance_m = 1.25;
  located.centre.clock_angle_deg = 92.0;
  located.centre.clock = "3:04";
  located.centre.point = {0.2, 0.0, 1.5};
  located.distance_from_m = 1.2;
  located.distance_to_m = 1.3;
  located.clock_from_deg = 80.0;
  located.clock_to_deg = 100.0;
  LocatedObservation missing;
  missing.observation.frame = 9;
  missing.why_not = "frame 9 has no pose in the run";
  const auto dir = MakeTestDirectory("observations_located");
  WriteLocatedObservationsCsv(dir / "located.csv", {located, missing});
  const std::vector<LocatedObservation> again = ReadLocatedObservationsCsv(dir / "located.csv");
  ASSERT_EQ(again.size(), 2u);
  EXPECT_TRUE(again[0].located);
  EXPECT_EQ(again[0].observation.remark, "say \"hi\", twice");
  EXPECT_DOUBLE_EQ(again[0].centre.distance_m, 1.25);
  EXPECT_EQ(again[0].clock_from, "2:40");
  EXPECT_EQ(again[0].clock_to, "3:20");
  EXPECT_DOUBLE_EQ(again[0].observation.v_max, 8.0);
  EXPECT_FALSE(again[1].located);
  EXPECT_EQ(again[1].why_not, "frame 9 has no pose in the run");
}

}  // namespace
}  // namespace pipescope
