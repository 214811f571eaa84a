#include "pipescope/io/trajectory.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "pipescope/util/atomic_file.h"
#include "pipescope/util/error.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

// Expects ReadTumTrajectory to throw InputError whose message contains `expected` (e.g. the
// file name and line number).
void ExpectReadError(const std::string& contents, const std::string& expected) {
  const auto path = MakeTestDirectory("tum_error") / "bad.tum";
  WriteTextFileAtomically(path, contents);
  try {
    ReadTumTrajectory(path);
    FAIL() << "expected InputError for:\n" << contents;
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find(expected), std::string::npos) << error.what();
  }
}

TEST(TumTrajectory, RoundTripPreservesValues) {
  Trajectory trajectory;
  for (int i = 0; i < 20; ++i) {
    StampedPose pose;
    pose.timestamp = 1.6e9 + 0.033333333 * i;  // Unix times need all nine decimals.
    pose.position = Eigen::Vector3d(0.1 * i + 1e-7, -2.0 / 3.0 * i, 1e-12 * i + 3.14159265358979);
    pose.rotation = Eigen::Quaterniond(
        Eigen::AngleAxisd(0.1 * i + 0.01, Eigen::Vector3d(1, 2, 3).normalized()));
    trajectory.push_back(pose);
  }
  const auto path = MakeTestDirectory("tum_round_trip") / "sub" / "trajectory.tum";
  WriteTumTrajectory(path, trajectory);
  EXPECT_EQ(ReadTextFile(path).rfind("#", 0), 0u) << "header comment line expected";
  const Trajectory read = ReadTumTrajectory(path);
  ASSERT_EQ(read.size(), trajectory.size());
  for (std::size_t i = 0; i < read.size(); ++i) {
    EXPECT_NEAR(read[i].timestamp, trajectory[i].timestamp, 1e-9);
    EXPECT_LT((read[i].position - trajectory[i].position).norm(), 1e-12);
    EXPECT_LT((read[i].rotation.coeffs() - trajectory[i].rotation.coeffs()).norm(), 1e-12);
  }
}

TEST(TumTrajectory, SkipsCommentsAndBlankLinesAndNormalisesQuaternions) {
  const auto path = MakeTestDirectory("tum_comments") / "t.tum";
  WriteTextFileAtomically(path,
                          "# timestamp tx ty tz qx qy qz qw\n"
                          "\n"
                          "   \t\n"
                          "1.0 1 2 3 0 0 0 2   # trailing comment\n"
                          "1.5\t4 5 6 0 0 1 1\r\n"
                          "1.5 -1e-3 +2 3 0 0 0 1\n");
  const Trajectory trajectory = ReadTumTrajectory(path);
  ASSERT_EQ(trajectory.size(), 3u);
  EXPECT_DOUBLE_EQ(trajectory[0].timestamp, 1.0);
  EXPECT_EQ(trajectory[0].position, Eigen::Vector3d(1, 2, 3));
  EXPECT_DOUBLE_EQ(trajectory[0].rotation.w(), 1.0);
  EXPECT_DOUBLE_EQ(trajectory[1].position.z(), 6.0);
  // (0, 0, 1, 1) normalised: a 90 degree turn about z, stored x y z w.
  EXPECT_NEAR(trajectory[1].rotation.z(), std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(trajectory[1].rotation.w(), std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(trajectory[1].rotation.x(), 0.0, 1e-15);
  EXPECT_DOUBLE_EQ(trajectory[2].position.x(), -1e-3);
  EXPECT_DOUBLE_EQ(trajectory[2].position.y(), 2.0);
}

TEST(TumTrajectory, MalformedLineNamesFileAndLine) {
  ExpectReadError("# header\n1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 1\n", "bad.tum:3");
  ExpectReadError("1.0 0 0 0 0 0 0 1\n\n2.0 0 x 0 0 0 0 1\n", "bad.tum:3");
  ExpectReadError("1.0 0 0 0 0 0 0 1 9\n", "bad.tum:1");
  ExpectReadError("1.0 0 0 0 0 0 0 1\n2.0 0 0 0.5abc 0 0 0 1\n", "bad.tum:2");
}

TEST(TumTrajectory, RejectsNonFiniteValues) {
  ExpectReadError("1.0 0 0 0 0 0 0 1\n2.0 nan 0 0 0 0 0 1\n", "bad.tum:2");
  ExpectReadError("1.0 0 0 inf 0 0 0 1\n", "bad.tum:1");
}

TEST(TumTrajectory, RejectsZeroQuaternion) {
  ExpectReadError("1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 0 0\n", "bad.tum:2");
}

TEST(TumTrajectory, RejectsDecreasingTimestamps) {
  ExpectReadError("1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 0 1\n# c\n1.5 0 0 0 0 0 0 1\n", "bad.tum:4");
}

TEST(TumTrajectory, EmptyOrMissingFileIsAnInputError) {
  ExpectReadError("", "bad.tum");
  ExpectReadError("# only a comment\n\n", "bad.tum");
  EXPECT_THROW(ReadTumTrajectory("/nonexistent/pipescope.tum"), InputError);
}

TEST(ToStampedPose, RoundTripsThroughAnIsometry) {
  Eigen::Isometry3d world_from_cam = Eigen::Isometry3d::Identity();
  world_from_cam.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).matrix();
  world_from_cam.translation() = Eigen::Vector3d(0.1, -0.2, 1.5);
  const StampedPose pose = ToStampedPose(2.5, world_from_cam);
  EXPECT_EQ(pose.timestamp, 2.5);
  EXPECT_TRUE(ToIsometry(pose).isApprox(world_from_cam, 1e-12));
}

}  // namespace
}  // namespace pipescope
