#pragma once

#include <filesystem>
#include <string>

namespace pipescope {

// What a SIGINT, SIGTERM or SIGHUP leaves behind: nothing. InstallInterruptionHandler() blocks both
// signals in every thread and waits for them on a thread of its own, which can then do what a
// signal handler may not (remove folders, log): it removes every path registered below, says so
// on standard error, and ends the process with status 128 + signal. Call it first in main(),
// before any other thread starts, so that every thread inherits the blocked mask.
void InstallInterruptionHandler();

// A temporary file or folder that an interruption must remove. The registration lasts as long
// as the object; Release() ends it early (the path has been renamed into place).
class RemoveOnInterruption {
 public:
  explicit RemoveOnInterruption(std::filesystem::path path);
  ~RemoveOnInterruption();
  RemoveOnInterruption(const RemoveOnInterruption&) = delete;
  RemoveOnInterruption& operator=(const RemoveOnInterruption&) = delete;

  void Release();

 private:
  std::filesystem::path path_;
  bool registered_ = false;
};

// Runs `step` so that an interruption waits for it to end: a rename that puts an output in
// place is not cut in half by the clean-up.
template <typename Step>
void WithoutInterruption(Step&& step);

namespace interruption_internal {
void Lock();
void Unlock();
}  // namespace interruption_internal

template <typename Step>
void WithoutInterruption(Step&& step) {
  interruption_internal::Lock();
  try {
    step();
  } catch (...) {
    interruption_internal::Unlock();
    throw;
  }
  interruption_internal::Unlock();
}

}  // namespace pipescope
