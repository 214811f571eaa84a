#include "pipescope/util/output_paths.h"

#include <gtest/gtest.h>

#include "pipescope/util/atomic_file.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

TEST(RefuseOutputOverInputs, RefusesTheSamePathInsideAndAbove) {
  const auto dir = MakeTestDirectory("output_paths");
  WriteTextFileAtomically(dir / "dataset" / "groundtruth.tum", "0 0 0 0 0 0 0 1\n");
  const std::vector<NamedInput> inputs = {{dir / "dataset", "the dataset"},
                                          {dir / "dataset" / "groundtruth.tum", "--gt"}};
  // The same folder, written as another path to it.
  const std::string same = InputErrorMessage(
      [&] { RefuseOutputOverInputs(dir / "dataset" / "." / "", "--out", inputs); });
  EXPECT_NE(same.find("--out"), std::string::npos);
  EXPECT_NE(same.find("is the dataset"), std::string::npos) << same;
  const std::string inside = InputErrorMessage(
      [&] { RefuseOutputOverInputs(dir / "dataset" / "mosaic.png", "--out", inputs); });
  EXPECT_NE(inside.find("lies inside the dataset"), std::string::npos) << inside;
  const std::string above =
      InputErrorMessage([&] { RefuseOutputOverInputs(dir, "--out", inputs); });
  EXPECT_NE(above.find("holds the dataset"), std::string::npos) << above;
  // A file reached through a symbolic link is the file.
  std::filesystem::create_symlink(dir / "dataset" / "groundtruth.tum", dir / "link.tum");
  const std::string linked =
      InputErrorMessage([&] { RefuseOutputOverInputs(dir / "link.tum", "--json", {{inputs[1]}}); });
  EXPECT_NE(linked.find("is --gt"), std::string::npos) << linked;
}

TEST(RefuseOutputOverInputs, AcceptsASiblingWithACommonPrefix) {
  const auto dir = MakeTestDirectory("output_paths_sibling");
  EXPECT_NO_THROW(RefuseOutputOverInputs(dir / "dataset-run", "--out",
                                         {{dir / "dataset", "the dataset"}, {"", "--camera"}}));
  EXPECT_NO_THROW(RefuseOutputOverInputs("", "--json", {{dir / "dataset", "the dataset"}}));
}

}  // namespace
}  // namespace pipescope
