#pragma once

#include <string>
#include <vector>

namespace pipescope {

// One line of a CSV file (RFC 4180): fields separated by commas, a field in double quotes may
// hold commas and doubled quotes. Throws std::invalid_argument for an unclosed quote.
std::vector<std::string> SplitCsvLine(const std::string& line);

// `text` as one CSV field: quoted when it holds a comma, a quote or a line break.
std::string CsvField(const std::string& text);

}  // namespace pipescope
