#include "pipescope/io/manifest_edit.h"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "pipescope/util/atomic_file.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

TEST(SetTopLevelYamlNumber, ReplacesTheKeyAndKeepsCommentsAndOtherKeys) {
  const auto dir = MakeTestDirectory("manifest_edit_replace");
  const auto path = dir / "dataset.yaml";
  WriteTextFileAtomically(path,
                          "# my pipe\nname: run1\ncamera: camera.yaml  # from calibrate\n"
                          "pipe:\n  inner_radius_m: 0.07666\n"
                          "reference_scale_px_per_m: 1000  # old\nvendor_key: [1, 2]\n");
  SetTopLevelYamlNumber(path, "reference_scale_px_per_m", 9537.123456789);
  EXPECT_EQ(ReadTextFile(path),
            "# my pipe\nname: run1\ncamera: camera.yaml  # from calibrate\n"
            "pipe:\n  inner_radius_m: 0.07666\n"
            "reference_scale_px_per_m: 9537.12345679  # old\nvendor_key: [1, 2]\n");
}

TEST(SetTopLevelYamlNumber, AppendsANewKeyAndIgnoresNestedNamesakes) {
  const auto dir = MakeTestDirectory("manifest_edit_append");
  const auto path = dir / "dataset.yaml";
  // A nested key of the same name is not the top-level one; no final newline either.
  WriteTextFileAtomically(path, "name: a\nextra:\n  reference_scale_px_per_m: 5");
  SetTopLevelYamlNumber(path, "reference_scale_px_per_m", 7448.5);
  EXPECT_EQ(ReadTextFile(path),
            "name: a\nextra:\n  reference_scale_px_per_m: 5\nreference_scale_px_per_m: 7448.5\n");
}

TEST(SetTopLevelYamlNumber, FlowStyleIsReEmittedWithItsValues) {
  const auto dir = MakeTestDirectory("manifest_edit_flow");
  const auto path = dir / "dataset.yaml";
  WriteTextFileAtomically(path, "{name: b, fps: 30, reference_scale_px_per_m: 1}\n");
  SetTopLevelYamlNumber(path, "reference_scale_px_per_m", 123.25);
  const YAML::Node node = YAML::LoadFile(path.string());
  EXPECT_EQ(node["name"].as<std::string>(), "b");
  EXPECT_EQ(node["fps"].as<int>(), 30);
  EXPECT_EQ(node["reference_scale_px_per_m"].as<double>(), 123.25);
}

TEST(SetTopLevelYamlNumber, BadFilesNameThemselves) {
  const auto dir = MakeTestDirectory("manifest_edit_bad");
  EXPECT_NE(InputErrorMessage([&] {
              SetTopLevelYamlNumber(dir / "missing.yaml", "k", 1.0);
            }).find("missing.yaml"),
            std::string::npos);
  WriteTextFileAtomically(dir / "list.yaml", "- 1\n- 2\n");
  EXPECT_NE(InputErrorMessage([&] {
              SetTopLevelYamlNumber(dir / "list.yaml", "k", 1.0);
            }).find("list.yaml"),
            std::string::npos);
  WriteTextFileAtomically(dir / "broken.yaml", "name: [unclosed\n");
  EXPECT_NE(InputErrorMessage([&] {
              SetTopLevelYamlNumber(dir / "broken.yaml", "k", 1.0);
            }).find("broken.yaml"),
            std::string::npos);
  EXPECT_EQ(ReadTextFile(dir / "broken.yaml"), "name: [unclosed\n");
}

}  // namespace
}  // namespace pipescope
