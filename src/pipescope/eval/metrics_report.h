#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "pipescope/eval/metrics.h"

namespace pipescope {

// metrics.json (GUIDE §4): exactly its keys, always all of them; keys that do not apply (the
// out-and-back errors of a one-way run, scale without sim3, rpe_1m_pct of a short run,
// junction_distances without junctions) are null.
nlohmann::json MetricsToJson(const Metrics& metrics);

// The same figures as an aligned text table for the terminal, one metric a line.
std::string MetricsToTable(const Metrics& metrics);

}  // namespace pipescope
