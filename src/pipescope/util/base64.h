#pragma once

#include <string>
#include <string_view>

namespace pipescope {

// Base64 (RFC 4648 §4, with padding) of `bytes`: how report.html carries images and point
// clouds inside one file.
std::string Base64Encode(std::string_view bytes);

// `mime` ("image/png") and Base64Encode(bytes) as a data: URL.
std::string DataUrl(const std::string& mime, std::string_view bytes);

}  // namespace pipescope
