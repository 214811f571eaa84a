#pragma once

#include <filesystem>
#include <string>

namespace pipescope {

// Sets top-level key `key` of the YAML mapping in `path` (a dataset.yaml, GUIDE §4) to the
// number `value`, rewriting the file atomically. Every other key keeps its value, including keys
// pipescope does not know. Block-style files, as pipescope and most people write them, are
// edited line by line so their comments and order survive: the key's line is replaced, or a line
// is appended when the key is new. Anything else (flow style, several documents) is re-emitted
// by yaml-cpp, which keeps values and drops comments. The result is parsed back and checked
// before it replaces the file. Throws InputError naming the file when it is missing, not YAML,
// or not a mapping.
void SetTopLevelYamlNumber(const std::filesystem::path& path, const std::string& key, double value);

}  // namespace pipescope
