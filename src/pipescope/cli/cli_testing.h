#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace pipescope {

struct CommandResult {
  int exit_status = -1;
  std::string output;  // stdout and stderr together
};

// Runs the `pipescope` program built beside the tests (PIPESCOPE_BINARY) with `arguments`, in
// the folder `working_directory` when one is given.
inline CommandResult RunPipescope(const std::string& arguments,
                                  const std::string& working_directory = "") {
  const std::string command =
      (working_directory.empty() ? "" : "cd " + working_directory + " && ") +
      std::string(PIPESCOPE_BINARY) + " " + arguments + " 2>&1";
  CommandResult result;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return result;
  std::array<char, 4096> buffer;
  while (fgets(buffer.data(), buffer.size(), pipe) != nullptr) result.output += buffer.data();
  const int status = pclose(pipe);
  result.exit_status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

}  // namespace pipescope
