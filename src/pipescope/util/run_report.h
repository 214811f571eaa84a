#pragma once

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pipescope/util/stage_times.h"

namespace pipescope {

// The program's version, from CMake's project() call.
const char* PipescopeVersion();

// Collects what a run did and writes it as run.json (GUIDE §4): the command, the method and its
// options, the version, timings, frame counts and warnings. Warnings are also logged.
class RunReport {
 public:
  explicit RunReport(std::string command);

  void SetMethod(const std::string& method) { method_ = method; }
  void SetOptions(nlohmann::json options) { options_ = std::move(options); }
  void AddTiming(const std::string& name, double seconds) { timings_[name] += seconds; }
  // Each stage's wall seconds as "PREFIX_STAGE" and its CPU seconds as "PREFIX_STAGE_cpu" (no
  // "PREFIX_" for an empty prefix).
  void AddStageTimes(const std::string& prefix, const StageTimes& times) {
    const std::string start = prefix.empty() ? "" : prefix + "_";
    for (const auto& [stage, seconds] : times.wall()) AddTiming(start + stage, seconds);
    for (const auto& [stage, seconds] : times.cpu()) AddTiming(start + stage + "_cpu", seconds);
  }
  void SetCount(const std::string& name, long long value) { counts_[name] = value; }
  void IncrementCount(const std::string& name, long long by = 1) { counts_[name] += by; }
  void Warn(const std::string& message);
  // Free-form extra sections (per-frame flags, classifications, ...).
  nlohmann::json& Extra(const std::string& key) { return extra_[key]; }

  const std::vector<std::string>& warnings() const { return warnings_; }
  long long Count(const std::string& name) const;

  nlohmann::json ToJson() const;
  void Write(const std::filesystem::path& path) const;

 private:
  std::string command_;
  std::string method_;
  nlohmann::json options_ = nlohmann::json::object();
  std::map<std::string, double> timings_;
  std::map<std::string, long long> counts_;
  std::vector<std::string> warnings_;
  nlohmann::json extra_ = nlohmann::json::object();
};

}  // namespace pipescope
