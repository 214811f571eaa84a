#include "pipescope/report/report_page.h"

#include <algorithm>
#include <stdexcept>

#include "pipescope/report/web_assets.h"
#include "pipescope/util/atomic_file.h"

namespace pipescope {

// Marker of the data in the template (report.html).
constexpr char kDataMarker[] = "@REPORT_DATA@";

std::string AssembleReportHtml(std::string page,
                               const std::vector<std::pair<std::string, std::string>>& parts) {
  // Each marker is found in the template before any replacement, so a library's text that
  // happens to contain a marker's characters is never replaced itself.
  std::vector<std::pair<std::size_t, const std::pair<std::string, std::string>*>> places;
  for (const auto& part : parts) {
    const std::size_t at = page.find(part.first);
    if (at == std::string::npos || page.find(part.first, at + 1) != std::string::npos) {
      throw std::logic_error("report template: marker " + part.first + " must occur exactly once");
    }
    places.emplace_back(at, &part);
  }
  std::sort(places.begin(), places.end());
  std::string out;
  std::size_t copied = 0;
  for (const auto& [at, part] : places) {
    out.append(page, copied, at - copied);
    out += part->second;
    copied = at + part->first.size();
  }
  out.append(page, copied, std::string::npos);
  return out;
}

std::string JsonForScriptElement(const nlohmann::json& data) {
  // ASCII only (U+2028 and U+2029 become \u escapes), and every '<' as \u003c: '<' occurs only
  // inside JSON strings, where the escape means the same, and then no "</script" or "<!--" in
  // the data can change how the page is parsed.
  const std::string text = data.dump(-1, ' ', /*ensure_ascii=*/true);
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    if (c == '<') {
      out += "\\u003c";
    } else {
      out += c;
    }
  }
  return out;
}

void WriteReportPage(const std::filesystem::path& run_dir, const std::filesystem::path& out,
                     const ReportOptions& options) {
  std::string page;
  std::vector<std::pair<std::string, std::string>> parts;
  for (const WebAsset& asset : EmbeddedWebAssets()) {
    if (std::string(asset.name) == "template") {
      page = std::string(asset.content);
    } else {
      parts.emplace_back(asset.name, std::string(asset.content));
    }
  }
  parts.emplace_back(kDataMarker, JsonForScriptElement(BuildReportData(run_dir, options)));
  WriteTextFileAtomically(out, AssembleReportHtml(std::move(page), parts));
}

}  // namespace pipescope
