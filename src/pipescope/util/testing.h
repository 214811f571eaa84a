#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <functional>
#include <string>

#include "pipescope/util/error.h"

namespace pipescope {

// A new empty directory under the system's temporary folder, unique per process and name, for
// tests that write files.
inline std::filesystem::path MakeTestDirectory(const std::string& name) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    ("pipescope_test_" + std::to_string(getpid()) + "_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
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
