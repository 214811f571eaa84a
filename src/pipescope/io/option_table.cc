#include "pipescope/io/option_table.h"

#include <cmath>
#include <cstdio>

#include "pipescope/io/yaml_helpers.h"

namespace pipescope {

std::string FormatOptionNumber(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.6g", value);
  return buffer;
}

void RequireOptionRange(double value, double low, double high, const std::string& where) {
  if (!(value >= low && value <= high)) {
    throw InputError(where + " must be in [" + FormatOptionNumber(low) + ", " +
                     FormatOptionNumber(high) + "], got " + FormatOptionNumber(value));
  }
}

YAML::Node LoadOptionFile(const std::filesystem::path& path) {
  const YAML::Node root = LoadYamlFile(path);
  if (!root.IsMap()) throw InputError(path.string() + ": expected a map of option keys");
  return root;
}

std::string FormatOptionKey(const std::string& name, const nlohmann::json& value,
                            const std::string& range, const std::string& unit,
                            const std::string& help) {
  std::string shown = value.is_string() ? value.get<std::string>() : value.dump();
  if (value.is_number_float()) shown = FormatOptionNumber(value.get<double>());
  std::string line = "  " + name;
  if (line.size() < 36) line.resize(36, ' ');
  line += " " + shown + (unit.empty() ? "" : " " + unit);
  if (line.size() < 56) line.resize(56, ' ');
  line += " " + range + "\n      " + help + "\n";
  return line;
}

}  // namespace pipescope
