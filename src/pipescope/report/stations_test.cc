#include "pipescope/report/stations.h"

#include <gtest/gtest.h>

#include <cmath>

#include "pipescope/util/atomic_file.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

// A camera looking along +Z, upright (-y up = world -Y), rolled by `roll_deg` about its axis.
StampedPose PoseAt(double t, const Eigen::Vector3d& position, double roll_deg = 0.0,
                   const Eigen::Vector3d& looking = Eigen::Vector3d::UnitZ()) {
  const Eigen::Quaterniond facing =
      Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), looking);
  const Eigen::Quaterniond roll(
      Eigen::AngleAxisd(roll_deg * M_PI / 180.0, Eigen::Vector3d::UnitZ()));
  StampedPose pose;
  pose.timestamp = t;
  pose.position = position;
  pose.rotation = facing * roll;
  return pose;
}

std::vector<int> Frames(std::size_t n) {
  std::vector<int> frames(n);
  for (std::size_t i = 0; i < n; ++i) frames[i] = static_cast<int>(i);
  return frames;
}

TEST(Stations, StraightAxisCountsFromTheStartInTheFirstDirectionAndKeepsIt) {
  // Out 0.5 m along -Z, then back 0.2 m, wandering sideways: distances 0 -> 0.5 -> 0.3.
  Trajectory trajectory;
  for (int i = 0; i <= 70; ++i) {
    const double along = i <= 50 ? 0.01 * i : 0.5 - 0.01 * (i - 50);
    trajectory.push_back(PoseAt(0.1 * i, {0.003 * std::sin(i), 0.002 * std::cos(i), 2.0 - along}));
  }
  const std::vector<Station> stations = ComputeStations(trajectory, Frames(71), {});
  EXPECT_NEAR(stations[50].distance_m, 0.5, 1e-12);
  EXPECT_NEAR(stations[70].distance_m, 0.3, 1e-12);
  EXPECT_EQ(stations[60].travel, -Eigen::Vector3d::UnitZ());
  EXPECT_NEAR(stations[20].speed_m_s, 0.1, 1e-9);   // 1 cm per 0.1 s, outwards
  EXPECT_NEAR(stations[60].speed_m_s, -0.1, 1e-9);  // backing up
}

TEST(Stations, RollIsTheCameraUprightsClockAngle) {
  StationOptions options;
  options.up = Eigen::Vector3d(0.0, -1.0, 0.0);
  Trajectory trajectory;
  for (int i = 0; i < 5; ++i) trajectory.push_back(PoseAt(i, {0, 0, 0.05 * i}, 30.0 * i));
  const std::vector<Station> stations = ComputeStations(trajectory, Frames(5), options);
  // Rolled by a about its optical axis (+z), the camera's upright -R e_y = (sin a, -cos a, 0)
  // leans towards +X, the right-hand side looking along +Z: clock angle a.
  for (int i = 0; i < 5; ++i) EXPECT_NEAR(stations[i].roll_clock_deg, 30.0 * i, 1e-9) << i;
}

TEST(Stations, TravelledPathFollowsABendWithoutTheWander) {
  // 1 m along +Z, a quarter circle of radius 0.3 m, 1 m along +X, with 3 mm sideways wobble.
  Trajectory trajectory;
  double t = 0.0;
  const auto add = [&](const Eigen::Vector3d& p) { trajectory.push_back(PoseAt(t += 0.1, p)); };
  for (int i = 0; i <= 200; ++i) add({0.003 * std::sin(0.7 * i), 0.0, 0.005 * i});
  const double bend = 0.3 * M_PI / 2.0;
  for (int i = 1; i <= 94; ++i) {
    const double a = (M_PI / 2.0) * i / 94.0;
    add({0.3 - 0.3 * std::cos(a), 0.0, 1.0 + 0.3 * std::sin(a)});
  }
  for (int i = 1; i <= 200; ++i) add({0.3 + 0.005 * i, 0.003 * std::sin(0.9 * i), 1.3});
  StationOptions options;
  options.line = SurveyLine::kTravelledPath;
  const std::vector<Station> stations =
      ComputeStations(trajectory, Frames(trajectory.size()), options);
  // The wobble alone adds about 1 % to the path length; the stations must not.
  EXPECT_NEAR(stations.back().distance_m, 2.0 + bend, 0.01);
  EXPECT_GT(stations.back().travel.dot(Eigen::Vector3d::UnitX()), std::cos(5.0 * M_PI / 180.0));
}

TEST(Stations, FrameIndicesFromFpsOrTimestampsFile) {
  Trajectory trajectory = {PoseAt(0.0, {0, 0, 0}), PoseAt(0.2, {0, 0, 0}), PoseAt(0.25, {0, 0, 0})};
  DatasetManifest manifest;
  manifest.fps = 10.0;
  EXPECT_EQ(FrameIndicesByTime(trajectory, manifest), (std::vector<int>{0, 2, -1}));
  const auto dir = MakeTestDirectory("stations_times");
  WriteTextFileAtomically(dir / "times.txt", "0.0\n0.05\n0.2\n0.26\n");
  manifest.timestamps_path = dir / "times.txt";
  EXPECT_EQ(FrameIndicesByTime(trajectory, manifest), (std::vector<int>{0, 2, 3}));
}

TEST(Stations, CsvRoundTrips) {
  Trajectory trajectory;
  for (int i = 0; i < 4; ++i) trajectory.push_back(PoseAt(0.5 * i, {0, 0, 0.1 * i}, 45.0 * i));
  const std::vector<Station> stations = ComputeStations(trajectory, {3, 4, 6, 7}, {});
  const auto dir = MakeTestDirectory("stations_csv");
  WriteStationsCsv(dir / "stations.csv", stations);
  const std::string text = ReadTextFile(dir / "stations.csv");
  EXPECT_EQ(text.rfind("frame,timestamp_s,distance_m,roll_clock_deg,roll_clock,speed_m_s\n", 0),
            0u);
  EXPECT_NE(text.find(",1:30,"), std::string::npos) << text;  // 45 degrees
  const std::vector<Station> again = ReadStationsCsv(dir / "stations.csv");
  ASSERT_EQ(again.size(), 4u);
  EXPECT_EQ(again[2].frame, 6);
  EXPECT_NEAR(again[3].distance_m, 0.3, 1e-9);
  EXPECT_NEAR(again[1].roll_clock_deg, 45.0, 1e-6);
  EXPECT_NEAR(again[1].speed_m_s, stations[1].speed_m_s, 1e-9);
}

}  // namespace
}  // namespace pipescope
