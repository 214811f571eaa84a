#include "pipescope/util/staging_directory.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

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

// The pid of a process that has ended, as a killed run leaves in its staging folder's name.
pid_t EndedProcess() {
  const pid_t child = fork();
  if (child == 0) _exit(0);
  waitpid(child, nullptr, 0);
  return child;
}

TEST(StagingDirectory, RemovesWhatKilledRunsLeftAndRestoresAHalfReplacedOutput) {
  const auto dir = MakeTestDirectory("staging_abandoned");
  const std::string dead = std::to_string(EndedProcess());
  WriteTextFileAtomically(dir / (".out.partial-" + dead) / "marker", "half");
  // A run killed between the two renames of a replacement: the old output sits aside.
  WriteTextFileAtomically(dir / (".out.old-" + dead) / "marker", "old");
  // Someone else's hidden folder of a live process stays.
  WriteTextFileAtomically(dir / (".out.partial-" + std::to_string(getpid())) / "x", "live");
  RemoveAbandonedStaging(dir / "out");
  EXPECT_FALSE(std::filesystem::exists(dir / (".out.partial-" + dead)));
  EXPECT_FALSE(std::filesystem::exists(dir / (".out.old-" + dead)));
  EXPECT_EQ(ReadTextFile(dir / "out" / "marker"), "old");
  EXPECT_TRUE(std::filesystem::exists(dir / (".out.partial-" + std::to_string(getpid()))));
}

TEST(StagingDirectory, RefusesTheWorkingDirectoryAndItsParents) {
  const auto dir = MakeTestDirectory("staging_cwd");
  std::filesystem::create_directories(dir / "work");
  const std::filesystem::path before = std::filesystem::current_path();
  std::filesystem::current_path(dir / "work");
  const std::string here =
      InputErrorMessage([&] { StagingDirectory staging(".", "--out", "marker"); });
  const std::string parent =
      InputErrorMessage([&] { StagingDirectory staging(dir, "--out", "marker"); });
  std::filesystem::current_path(before);
  EXPECT_NE(here.find("working directory"), std::string::npos) << here;
  EXPECT_NE(parent.find("working directory"), std::string::npos) << parent;
}

TEST(AtomicFile, RemovesTemporariesOfKilledWriters) {
  const auto dir = MakeTestDirectory("atomic_abandoned");
  const std::string dead = std::to_string(EndedProcess());
  WriteTextFileAtomically(dir / (".mosaic.tmp" + dead + "_0.png"), "half");
  WriteTextFileAtomically(dir / "mosaic.png", "whole");
  EXPECT_FALSE(std::filesystem::exists(dir / (".mosaic.tmp" + dead + "_0.png")));
  EXPECT_EQ(ReadTextFile(dir / "mosaic.png"), "whole");
}

}  // namespace
}  // namespace pipescope
