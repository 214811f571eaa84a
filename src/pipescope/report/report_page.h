#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "pipescope/report/report_data.h"

namespace pipescope {

// The page with each marker replaced by its contents. Every marker must occur exactly once in
// `page` (std::logic_error otherwise: the template and the embedded files disagree).
std::string AssembleReportHtml(std::string page,
                               const std::vector<std::pair<std::string, std::string>>& parts);

// The report's JSON as it sits inside <script type="application/json">: every '<' escaped, so
// no string in the data can end the script element; JSON.parse reads it back unchanged.
std::string JsonForScriptElement(const nlohmann::json& data);

// report.html of a run directory (docs/formats.md): the embedded template, its style, script
// and libraries, and BuildReportData's JSON, written atomically to `out`.
void WriteReportPage(const std::filesystem::path& run_dir, const std::filesystem::path& out,
                     const ReportOptions& options);

}  // namespace pipescope
