#include "pipescope/cli/flag_checks.h"

#include <cmath>
#include <cstdio>

namespace pipescope {
namespace {

std::string Short(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.6g", value);
  return buffer;
}

}  // namespace

CLI::Validator FiniteRange(double low, double high, bool low_open) {
  const std::string range = (low_open ? "(" : "[") + Short(low) + ", " + Short(high) + "]";
  return CLI::Validator(
      [low, high, low_open, range](std::string& input) -> std::string {
        double value = 0.0;
        std::size_t used = 0;
        try {
          value = std::stod(input, &used);
        } catch (const std::exception&) {
          return "'" + input + "' is not a number";
        }
        if (used != input.size() || !std::isfinite(value)) {
          return "'" + input + "' is not a finite number";
        }
        if (value < low || (low_open && value == low) || value > high) {
          return input + " is outside " + range;
        }
        return {};
      },
      "NUMBER in " + range);
}

}  // namespace pipescope
