#pragma once

#include <chrono>
#include <ctime>

namespace pipescope {

// Wall-clock stopwatch for run.json timings.
class Timer {
 public:
  Timer() : start_(std::chrono::steady_clock::now()) {}
  double ElapsedSeconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  // Seconds since construction or the previous Lap(), and restarts: for timing stages of a loop.
  double Lap() {
    const auto now = std::chrono::steady_clock::now();
    const double seconds = std::chrono::duration<double>(now - start_).count();
    start_ = now;
    return seconds;
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

// CPU seconds of one clock (CLOCK_THREAD_CPUTIME_ID, CLOCK_PROCESS_CPUTIME_ID) since construction.
template <clockid_t kClock>
class CpuTimer {
 public:
  CpuTimer() : start_(Now()) {}
  double ElapsedSeconds() const { return Now() - start_; }

 private:
  static double Now() {
    timespec now{};
    clock_gettime(kClock, &now);
    return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
  }
  double start_;
};

// CPU seconds of the calling thread: what a loop costs one core, whatever else the machine runs
// (decoding on a read-ahead thread, other processes); for run.json's speed figures.
using ThreadCpuTimer = CpuTimer<CLOCK_THREAD_CPUTIME_ID>;
// CPU seconds of every thread of the process (OpenCV's workers included): what a run costs the
// machine, which wall time on a shared machine does not tell.
using ProcessCpuTimer = CpuTimer<CLOCK_PROCESS_CPUTIME_ID>;

}  // namespace pipescope
