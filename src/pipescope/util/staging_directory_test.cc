#include "pipescope/util/staging_directory.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "pipescope/util/atomic_file.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

std::size_t Entries(const std::filesystem::path& dir) {
  return std::distance(std::filesystem::directory_iterator(dir),
                       std::filesystem::directory_iterator());
}

TEST(StagingDirectory, CommitMovesTheFolderIntoPlace) {
  const auto dir = MakeTestDirectory("staging_commit");
  {
    StagingDirectory staging(dir / "out", "--out", "marker");
    WriteTextFileAtomically(staging.path() / "marker", "1");
    EXPECT_FALSE(std::filesystem::exists(dir / "out"));
    staging.Commit();
  }
  EXPECT_EQ(ReadTextFile(dir / "out" / "marker"), "1");
  // A second run replaces its own earlier output.
  {
    StagingDirectory staging(dir / "out", "--out", "marker");
    WriteTextFileAtomically(staging.path() / "marker", "2");
    staging.Commit();
  }
  EXPECT_EQ(ReadTextFile(dir / "out" / "marker"), "2");
  EXPECT_EQ(Entries(dir), 1u);
}

TEST(StagingDirectory, FailureLeavesTheTargetAlone) {
  const auto dir = MakeTestDirectory("staging_fail");
  WriteTextFileAtomically(dir / "out" / "marker", "old");
  try {
    StagingDirectory staging(dir / "out", "--out", "marker");
    WriteTextFileAtomically(staging.path() / "marker", "half");
    throw std::runtime_error("render failed");
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(ReadTextFile(dir / "out" / "marker"), "old");
  EXPECT_EQ(Entries(dir), 1u);
}

TEST(StagingDirectory, RefusesAForeignFolder) {
  const auto dir = MakeTestDirectory("staging_refuse");
  WriteTextFileAtomically(dir / "photos" / "holiday.jpg", "x");
  const std::string message =
      InputErrorMessage([&] { StagingDirectory staging(dir / "photos", "--out", "marker"); });
  EXPECT_NE(message.find("--out"), std::string::npos);
  EXPECT_NE(message.find("photos"), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(dir / "photos" / "holiday.jpg"));
}

}  // namespace
}  // namespace pipescope
