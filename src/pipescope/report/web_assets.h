#pragma once

#include <string_view>
#include <vector>

namespace pipescope {

// A file embedded in the program for report.html (cmake/web_assets.cmake): `name` is "template"
// for the page, else the marker of the page that the file's contents replace.
struct WebAsset {
  const char* name;
  std::string_view content;
};

// The page's template, its own style and script, and the pinned JavaScript libraries.
const std::vector<WebAsset>& EmbeddedWebAssets();

}  // namespace pipescope
