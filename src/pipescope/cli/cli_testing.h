#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdint>
#include <cstdio>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
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

// Overwrites a dataset's frames [first, end) (images/%06d.png) with plain noise about mid-grey
// (sigma 3 grey levels): frames that show nothing to track. False when a frame cannot be written.
inline bool WritePlainNoiseFrames(const std::string& dataset, int first, int end, int width,
                                  int height, std::uint64_t seed) {
  cv::RNG rng(seed);
  for (int index = first; index < end; ++index) {
    cv::Mat plain(height, width, CV_8U);
    rng.fill(plain, cv::RNG::NORMAL, 120.0, 3.0);
    char name[32];
    std::snprintf(name, sizeof(name), "/images/%06d.png", index);
    if (!cv::imwrite(dataset + name, plain)) return false;
  }
  return true;
}

}  // namespace pipescope
