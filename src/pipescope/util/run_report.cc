#include "pipescope/util/run_report.h"

#include <spdlog/spdlog.h>

#include "pipescope/util/atomic_file.h"

namespace pipescope {

const char* PipescopeVersion() { return PIPESCOPE_VERSION; }

RunReport::RunReport(std::string command) : command_(std::move(command)) {}

void RunReport::Warn(const std::string& message) {
  spdlog::warn("{}", message);
  warnings_.push_back(message);
}

long long RunReport::Count(const std::string& name) const {
  const auto it = counts_.find(name);
  return it == counts_.end() ? 0 : it->second;
}

nlohmann::json RunReport::ToJson() const {
  nlohmann::json json;
  json["command"] = command_;
  if (!method_.empty()) json["method"] = method_;
  json["options"] = options_;
  json["version"] = PipescopeVersion();
  json["timings_s"] = timings_;
  json["counts"] = counts_;
  json["warnings"] = warnings_;
  for (const auto& [key, value] : extra_.items()) json[key] = value;
  return json;
}

void RunReport::Write(const std::filesystem::path& path) const {
  WriteTextFileAtomically(path, ToJson().dump(2) + "\n");
}

}  // namespace pipescope
