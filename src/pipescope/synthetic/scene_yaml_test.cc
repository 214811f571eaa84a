#include "pipescope/synthetic/scene_yaml.h"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <stdexcept>

#include "pipescope/io/junctions.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

using Eigen::Vector3d;

Vector3d ReadVector(const YAML::Node& node) {
  EXPECT_TRUE(node.IsSequence());
  EXPECT_EQ(node.size(), 3u);
  return Vector3d(node[0].as<double>(), node[1].as<double>(), node[2].as<double>());
}

// start straight, tee T1, straight, bend, straight, tee "T 2: x" (needs quoting).
Scene SmallNetwork() {
  Scene scene;
  const double radius = 0.2;
  scene.AddStraight(Vector3d(0, 0, -1.5), Vector3d(0, 0, 1.0 / 3.0), radius);
  scene.AddTee("T1", Vector3d(0, 0, 0));
  scene.AddStraight(Vector3d(0, 0, 0), Vector3d(2, 0, 0), radius);
  scene.AddBend(Vector3d(2, 0, 0), Vector3d::UnitX(), Vector3d::UnitZ(), 0.7, std::numbers::pi / 3,
                radius);
  const PipeSection& bend = scene.sections()[2];
  const Vector3d end = bend.EndPoint() + 3 * bend.EndDirection();
  scene.AddStraight(bend.EndPoint(), end, radius);
  scene.AddTee("T 2: x", end);
  return scene;
}

TEST(SceneYaml, WritesSectionsInRouteOrderAndJunctions) {
  const auto path = MakeTestDirectory("scene_yaml") / "scene.yaml";
  const Scene scene = SmallNetwork();
  WriteSceneYaml(path, scene);

  const YAML::Node root = YAML::LoadFile(path.string());
  EXPECT_EQ(root["radius"].as<double>(), 0.2);
  const YAML::Node sections = root["sections"];
  ASSERT_TRUE(sections.IsSequence());
  ASSERT_EQ(sections.size(), 6u);
  const char* types[] = {"straight", "tee", "straight", "bend", "straight", "tee"};
  for (int i = 0; i < 6; ++i) EXPECT_EQ(sections[i]["type"].as<std::string>(), types[i]) << i;

  // Full precision: doubles read back bit for bit.
  EXPECT_EQ(ReadVector(sections[0]["start"]), Vector3d(0, 0, -1.5));
  EXPECT_EQ(ReadVector(sections[0]["end"]), Vector3d(0, 0, 1.0 / 3.0));
  EXPECT_EQ(sections[0]["radius"].as<double>(), 0.2);
  EXPECT_EQ(sections[1]["name"].as<std::string>(), "T1");
  EXPECT_EQ(ReadVector(sections[1]["center"]), Vector3d::Zero());
  EXPECT_EQ(ReadVector(sections[2]["end"]), Vector3d(2, 0, 0));

  const PipeSection& bend = scene.sections()[2];
  const YAML::Node yaml_bend = sections[3];
  EXPECT_EQ(ReadVector(yaml_bend["start"]), Vector3d(2, 0, 0));
  EXPECT_EQ(ReadVector(yaml_bend["center"]), Vector3d(2, 0, 0.7));
  EXPECT_EQ(ReadVector(yaml_bend["end"]), bend.EndPoint());
  // Closed form of a 60 degree turn from +X towards +Z about the centre (2, 0, 0.7).
  EXPECT_LT((ReadVector(yaml_bend["end"]) - Vector3d(2 + 0.7 * std::sqrt(3.0) / 2, 0, 0.35)).norm(),
            1e-15);
  EXPECT_EQ(ReadVector(yaml_bend["axis"]), bend.bend_axis);
  EXPECT_EQ(yaml_bend["bend_radius"].as<double>(), 0.7);
  EXPECT_NEAR(yaml_bend["angle_deg"].as<double>(), 60, 1e-12);
  EXPECT_EQ(yaml_bend["radius"].as<double>(), 0.2);
  EXPECT_EQ(ReadVector(sections[4]["start"]), bend.EndPoint());
  EXPECT_EQ(sections[5]["name"].as<std::string>(), "T 2: x");

  const YAML::Node junctions = root["junctions"];
  ASSERT_EQ(junctions.size(), 2u);
  EXPECT_EQ(junctions[1]["name"].as<std::string>(), "T 2: x");

  // The reader the evaluation uses gets the names and centres exactly.
  const auto read = ReadSceneJunctions(path);
  ASSERT_EQ(read.size(), 2u);
  EXPECT_EQ(read[0].name, "T1");
  EXPECT_EQ(read[0].center, Vector3d::Zero());
  EXPECT_EQ(read[1].name, "T 2: x");
  EXPECT_EQ(read[1].center, scene.junctions()[1].center);

  // Atomic writing leaves no temporary behind.
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(path.parent_path())) {
    (void)entry;
    ++files;
  }
  EXPECT_EQ(files, 1);
}

TEST(SceneYaml, StraightPipeHasNoJunctions) {
  const auto path = MakeTestDirectory("scene_yaml_straight") / "scene.yaml";
  Scene scene;
  scene.AddStraight(Vector3d::Zero(), Vector3d(0, 0, 6), 0.07666);
  WriteSceneYaml(path, scene);
  const YAML::Node root = YAML::LoadFile(path.string());
  EXPECT_EQ(root["radius"].as<double>(), 0.07666);
  EXPECT_EQ(root["sections"].size(), 1u);
  EXPECT_TRUE(root["junctions"].IsSequence());
  EXPECT_TRUE(ReadSceneJunctions(path).empty());

  EXPECT_THROW(WriteSceneYaml(path, Scene()), std::invalid_argument);
}

}  // namespace
}  // namespace pipescope
