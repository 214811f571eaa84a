#pragma once

#include <map>
#include <string>

#include "pipescope/util/timer.h"

namespace pipescope {

// Where a run's time went: wall seconds and CPU seconds of named stages, summed over a loop. The
// one way the pipelines time their stages for run.json (RunReport::AddStageTimes).
class StageTimes {
 public:
  void Add(const std::string& stage, double wall_seconds, double cpu_seconds) {
    wall_[stage] += wall_seconds;
    cpu_[stage] += cpu_seconds;
  }
  // A stage of waiting, which has wall seconds only.
  void AddWall(const std::string& stage, double wall_seconds) { wall_[stage] += wall_seconds; }
  // Adds every stage of `other` (stages timed on another thread).
  void Merge(const StageTimes& other) {
    for (const auto& [stage, seconds] : other.wall_) wall_[stage] += seconds;
    for (const auto& [stage, seconds] : other.cpu_) cpu_[stage] += seconds;
  }
  const std::map<std::string, double>& wall() const { return wall_; }
  const std::map<std::string, double>& cpu() const { return cpu_; }

 private:
  std::map<std::string, double> wall_;
  std::map<std::string, double> cpu_;
};

// Times one stage from its construction: wall seconds, and CPU seconds of the calling thread
// (ThreadCpuTimer: what the stage costs one core) or of the whole process (ProcessCpuTimer:
// OpenCV's and Ceres' workers included).
template <typename CpuClock = ThreadCpuTimer>
class StageClock {
 public:
  double WallSeconds() const { return wall_.ElapsedSeconds(); }
  double CpuSeconds() const { return cpu_.ElapsedSeconds(); }
  // Adds the time since construction to `stage` of `times` (nothing when null).
  void AddTo(StageTimes* times, const std::string& stage) const {
    if (times) times->Add(stage, WallSeconds(), CpuSeconds());
  }

 private:
  Timer wall_;
  CpuClock cpu_;
};

}  // namespace pipescope
