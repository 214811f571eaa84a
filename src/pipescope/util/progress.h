#pragma once

#include <chrono>
#include <cstddef>
#include <string>

namespace pipescope {

// A one-line progress bar on stderr. It draws only when stderr is a terminal and logging is not
// quiet, and at most ten times a second, so it costs nothing in batch runs and CI logs.
class ProgressBar {
 public:
  // `total` may be 0 when the length is unknown; then only the count is shown.
  ProgressBar(std::string label, std::size_t total);
  ~ProgressBar();

  void Update(std::size_t done);
  void Finish();

 private:
  void Draw(std::size_t done);

  std::string label_;
  std::size_t total_;
  bool enabled_;
  bool finished_ = false;
  std::size_t last_done_ = 0;
  std::chrono::steady_clock::time_point last_draw_;
};

}  // namespace pipescope
