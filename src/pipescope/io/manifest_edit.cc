#include "pipescope/io/manifest_edit.h"

#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <optional>
#include <regex>
#include <vector>

#include "pipescope/util/atomic_file.h"
#include "pipescope/util/error.h"

namespace pipescope {
namespace {

std::optional<YAML::Node> ParseMap(const std::string& text) {
  try {
    YAML::Node node = YAML::Load(text);
    if (node.IsMap()) return node;
  } catch (const YAML::Exception&) {
  }
  return std::nullopt;
}

// Whether `edited` holds `key` = `value` and every other key of `original` unchanged.
bool IsFaithfulEdit(const YAML::Node& original, const std::string& edited, const std::string& key,
                    double value) {
  const std::optional<YAML::Node> result = ParseMap(edited);
  if (!result || result->size() != original.size() + (original[key] ? 0 : 1)) return false;
  for (const auto& entry : original) {
    const std::string name = entry.first.as<std::string>();
    if (name == key) continue;
    if (!(*result)[name] || YAML::Dump((*result)[name]) != YAML::Dump(entry.second)) return false;
  }
  try {
    return (*result)[key].as<double>() == value;
  } catch (const YAML::Exception&) {
    return false;
  }
}

// Line-by-line edit of a block-style mapping; empty when the text does not look like one.
std::optional<std::string> EditLines(const std::string& text, const std::string& key,
                                     const std::string& value_text) {
  std::vector<std::string> lines;
  std::size_t begin = 0;
  while (begin < text.size()) {
    const std::size_t end = text.find('\n', begin);
    lines.push_back(text.substr(begin, end == std::string::npos ? std::string::npos : end - begin));
    if (end == std::string::npos) break;
    begin = end + 1;
  }
  const std::regex key_line(
      "^" + std::regex_replace(key, std::regex(R"([.^$|()\[\]{}*+?\\])"), R"(\$&)") +
      R"([ \t]*:([ \t].*)?\r?$)");
  int matches = 0;
  std::size_t match = 0;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (std::regex_match(lines[i], key_line)) {
      ++matches;
      match = i;
    }
  }
  if (matches > 1) return std::nullopt;
  if (matches == 1) {
    // Keep a trailing comment on the replaced line.
    std::size_t comment = lines[match].find(" #");
    while (comment != std::string::npos && comment > 0 &&
           (lines[match][comment - 1] == ' ' || lines[match][comment - 1] == '\t')) {
      --comment;
    }
    lines[match] = key + ": " + value_text +
                   (comment == std::string::npos ? std::string() : lines[match].substr(comment));
  } else {
    if (!lines.empty() && lines.back().empty()) lines.pop_back();
    lines.push_back(key + ": " + value_text);
  }
  std::string result;
  for (const std::string& line : lines) result += line + "\n";
  return result;
}

}  // namespace

void SetTopLevelYamlNumber(const std::filesystem::path& path, const std::string& key,
                           double value) {
  const std::string text = ReadTextFile(path);
  const std::optional<YAML::Node> original = ParseMap(text);
  if (!original) throw InputError(path.string() + " is not a YAML mapping (a dataset.yaml)");
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.12g", value);
  const std::string value_text = buffer;
  const double written = std::stod(value_text);

  std::optional<std::string> edited = EditLines(text, key, value_text);
  if (!edited || !IsFaithfulEdit(*original, *edited, key, written)) {
    YAML::Node node = YAML::Clone(*original);
    node[key] = written;
    YAML::Emitter out;
    out.SetDoublePrecision(12);
    out << node;
    edited = std::string(out.c_str()) + "\n";
    if (!IsFaithfulEdit(*original, *edited, key, written)) {
      throw std::runtime_error("cannot set " + key + " in " + path.string());
    }
  }
  WriteTextFileAtomically(path, *edited);
}

}  // namespace pipescope
