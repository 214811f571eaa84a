#include "pipescope/report/report_page.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "pipescope/report/web_assets.h"

namespace pipescope {
namespace {

TEST(ReportPage, ReplacesEachMarkerOnceAndNotInsideReplacements) {
  const std::string page = "<a>/*@A@*/</a><b>@DATA@</b>";
  // A replacement that itself holds another marker's text stays as it is.
  EXPECT_EQ(AssembleReportHtml(page, {{"/*@A@*/", "x@DATA@x"}, {"@DATA@", "{}"}}),
            "<a>x@DATA@x</a><b>{}</b>");
  EXPECT_THROW(AssembleReportHtml(page, {{"@MISSING@", ""}}), std::logic_error);
  EXPECT_THROW(AssembleReportHtml("@D@ @D@", {{"@D@", ""}}), std::logic_error);
}

TEST(ReportPage, DataCannotCloseItsScriptElement) {
  const nlohmann::json data = {{"remark", "</script><script>alert(1)</script> <!-- \u2028"},
                               {"values", {1.5, -2, nullptr}}};
  const std::string text = JsonForScriptElement(data);
  EXPECT_EQ(text.find('<'), std::string::npos) << text;
  EXPECT_EQ(nlohmann::json::parse(text), data);
  for (const char c : text) EXPECT_LT(static_cast<unsigned char>(c), 128) << text;
}

// The template and the embedded files agree: the program can assemble the page.
TEST(ReportPage, EmbeddedTemplateHoldsEveryMarkerOnce) {
  std::string page;
  std::vector<std::pair<std::string, std::string>> parts = {{"@REPORT_DATA@", "{}"}};
  for (const WebAsset& asset : EmbeddedWebAssets()) {
    EXPECT_FALSE(asset.content.empty()) << asset.name;
    if (std::string(asset.name) == "template") {
      page = std::string(asset.content);
    } else {
      parts.emplace_back(asset.name, "");
    }
  }
  ASSERT_FALSE(page.empty());
  EXPECT_NO_THROW(AssembleReportHtml(page, parts));
}

}  // namespace
}  // namespace pipescope
