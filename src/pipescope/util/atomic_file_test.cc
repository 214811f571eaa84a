#include "pipescope/util/atomic_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <stdexcept>

#include "pipescope/util/error.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

TEST(AtomicFile, WritesAndReadsBack) {
  const auto dir = MakeTestDirectory("atomic_ok");
  WriteTextFileAtomically(dir / "sub" / "a.txt", "hello\n");
  EXPECT_EQ(ReadTextFile(dir / "sub" / "a.txt"), "hello\n");
  // Only the final file remains: no temporary left behind.
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir / "sub"),
                          std::filesystem::directory_iterator()),
            1);
}

TEST(AtomicFile, FailedWriterLeavesNothingAndKeepsOldFile) {
  const auto dir = MakeTestDirectory("atomic_fail");
  WriteTextFileAtomically(dir / "a.txt", "old");
  EXPECT_THROW(WriteFileAtomically(dir / "a.txt",
                                   [](const std::filesystem::path& temporary) {
                                     WriteTextFileAtomically(temporary, "half");
                                     throw std::runtime_error("writer failed");
                                   }),
               std::runtime_error);
  EXPECT_EQ(ReadTextFile(dir / "a.txt"), "old");
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir),
                          std::filesystem::directory_iterator()),
            1);
}

TEST(AtomicFile, MissingFileNamesThePath) {
  try {
    ReadTextFile("/nonexistent/pipescope.txt");
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("/nonexistent/pipescope.txt"), std::string::npos);
  }
}

}  // namespace
}  // namespace pipescope
