#include "pipescope/io/junctions.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "pipescope/util/atomic_file.h"
#include "pipescope/util/error.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

TEST(Junctions, ReadsSceneJunctionsAndIgnoresOtherKeys) {
  const auto path = MakeTestDirectory("scene_junctions") / "scene.yaml";
  WriteTextFileAtomically(path,
                          "inner_radius_m: 0.1\n"
                          "sections:\n"
                          "  - {start: [0, 0, 0], end: [0, 0, 2]}\n"
                          "junctions:\n"
                          "  - name: T1\n"
                          "    center: [0, 0, 2]\n"
                          "    branch: [1, 0, 0]\n"
                          "  - {name: T2, center_m: [1.5, -0.25, 4e0]}\n");
  const auto junctions = ReadSceneJunctions(path);
  ASSERT_EQ(junctions.size(), 2u);
  EXPECT_EQ(junctions[0].name, "T1");
  EXPECT_EQ(junctions[0].center, Eigen::Vector3d(0, 0, 2));
  EXPECT_TRUE(std::isnan(junctions[0].timestamp));
  EXPECT_EQ(junctions[1].name, "T2");
  EXPECT_EQ(junctions[1].center, Eigen::Vector3d(1.5, -0.25, 4));
}

TEST(Junctions, SceneWithoutJunctionsHasNone) {
  const auto path = MakeTestDirectory("scene_no_junctions") / "scene.yaml";
  WriteTextFileAtomically(path, "inner_radius_m: 0.1\n");
  EXPECT_TRUE(ReadSceneJunctions(path).empty());
}

TEST(Junctions, WriteReadRoundTripIsExact) {
  const auto path = MakeTestDirectory("junctions_round_trip") / "run" / "junctions.yaml";
  std::vector<Junction> junctions(2);
  junctions[0] = {"J0", 12.345678901, Eigen::Vector3d(0.1, 1.0 / 3.0, -2e-9)};
  junctions[1] = {"junction: 1", 20.0, Eigen::Vector3d(4, 5, 6)};  // Needs YAML quoting.
  junctions[1].axes = {Eigen::Vector3d(0.6, 0.0, 0.8), Eigen::Vector3d(0, -1, 0)};
  WriteEstimatedJunctions(path, junctions);
  const auto read = ReadEstimatedJunctions(path);
  ASSERT_EQ(read.size(), 2u);
  for (std::size_t i = 0; i < read.size(); ++i) {
    EXPECT_EQ(read[i].name, junctions[i].name);
    EXPECT_EQ(read[i].timestamp, junctions[i].timestamp);
    EXPECT_EQ(read[i].center, junctions[i].center);
    ASSERT_EQ(read[i].axes.size(), junctions[i].axes.size());
    for (std::size_t a = 0; a < read[i].axes.size(); ++a) {
      EXPECT_LT((read[i].axes[a] - junctions[i].axes[a]).norm(), 1e-15);
    }
  }
  WriteEstimatedJunctions(path, {});
  EXPECT_TRUE(ReadEstimatedJunctions(path).empty());
}

TEST(Junctions, ErrorsNameFileAndKey) {
  const auto dir = MakeTestDirectory("junctions_errors");
  const auto path = dir / "junctions.yaml";
  WriteTextFileAtomically(path,
                          "junctions:\n  - {name: A, timestamp: 1, center: [0, 0, 0]}\n"
                          "  - {name: B, center: [0, 0, 1]}\n");
  std::string message = InputErrorMessage([&] { ReadEstimatedJunctions(path); });
  EXPECT_NE(message.find("junctions.yaml:3"), std::string::npos) << message;
  EXPECT_NE(message.find("junctions[1]"), std::string::npos) << message;
  EXPECT_NE(message.find("timestamp"), std::string::npos) << message;

  WriteTextFileAtomically(path,
                          "junctions:\n  - {name: A, timestamp: 1, center: [0, 0, 0], "
                          "axes: [[1, 0, 0], [0, 0, 0]]}\n");
  message = InputErrorMessage([&] { ReadEstimatedJunctions(path); });
  EXPECT_NE(message.find("junctions[0].axes[1]"), std::string::npos) << message;

  WriteTextFileAtomically(path, "junctions:\n  - {name: A, timestamp: 1, center: [0, 0]}\n");
  message = InputErrorMessage([&] { ReadEstimatedJunctions(path); });
  EXPECT_NE(message.find("junctions[0].center"), std::string::npos) << message;

  WriteTextFileAtomically(path, "junctions:\n  - {name: A, timestamp: x, center: [0, 0, 0]}\n");
  message = InputErrorMessage([&] { ReadEstimatedJunctions(path); });
  EXPECT_NE(message.find("junctions[0].timestamp"), std::string::npos) << message;

  WriteTextFileAtomically(path, "other: 1\n");
  message = InputErrorMessage([&] { ReadEstimatedJunctions(path); });
  EXPECT_NE(message.find("junctions.yaml: missing key `junctions`"), std::string::npos) << message;

  WriteTextFileAtomically(path, "junctions: [\n");
  message = InputErrorMessage([&] { ReadEstimatedJunctions(path); });
  EXPECT_NE(message.find("junctions.yaml:"), std::string::npos) << message;

  const auto scene = dir / "scene.yaml";
  WriteTextFileAtomically(scene,
                          "junctions:\n  - {name: T, center: [0, 0, 0]}\n"
                          "  - {name: T, center: [0, 0, 1]}\n");
  message = InputErrorMessage([&] { ReadSceneJunctions(scene); });
  EXPECT_NE(message.find("scene.yaml:3"), std::string::npos) << message;
  EXPECT_NE(message.find("duplicate"), std::string::npos) << message;
}

}  // namespace
}  // namespace pipescope
