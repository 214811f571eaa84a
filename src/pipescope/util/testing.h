#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <functional>
#include <string>
#include <system_error>
#include <vector>

#include "pipescope/util/error.h"

namespace pipescope {

// The directories a test process made, removed when it exits so that repeated test runs do not
// fill the temporary folder; PIPESCOPE_KEEP_TEST_FILES=1 keeps them for inspection.
class TestDirectories {
 public:
  TestDirectories() = default;
  TestDirectories(const TestDirectories&) = delete;
  TestDirectories& operator=(const TestDirectories&) = delete;
  ~TestDirectories() {
    const char* keep = std::getenv("PIPESCOPE_KEEP_TEST_FILES");
    if (keep != nullptr && std::string(keep) == "1") return;
    std::error_code ignored;  // nothing useful to do about a failure at exit
    for (const std::filesystem::path& dir : dirs_) std::filesystem::remove_all(dir, ignored);
  }
  void Add(const std::filesystem::path& dir) { dirs_.push_back(dir); }

 private:
  std::vector<std::filesystem::path> dirs_;
};

// A new empty directory under the system's temporary folder, unique per process and name, for
// tests that write files; removed when the process exits (TestDirectories).
inline std::filesystem::path MakeTestDirectory(const std::string& name) {
  static TestDirectories made;
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    ("pipescope_test_" + std::to_string(getpid()) + "_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  made.Add(dir);
  return dir;
}

// The message of the InputError that `action` throws; a test failure and "" when it throws none.
inline std::string InputErrorMessage(const std::function<void()>& action) {
  try {
    action();
  } catch (const InputError& error) {
    return error.what();
  }
  ADD_FAILURE() << "expected InputError";
  return "";
}

}  // namespace pipescope
