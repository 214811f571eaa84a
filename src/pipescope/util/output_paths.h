#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace pipescope {

// An input a command reads, for RefuseOutputOverInputs(): the path and how the user gave it
// ("the dataset", "--gt", ...).
struct NamedInput {
  std::filesystem::path path;
  std::string name;
};

// Refuses, with InputError naming both flags, an output that would overwrite or remove an input
// before any work starts: an output path equal to an input, lying inside an input folder, or
// (an output folder that gets replaced whole) holding an input. Paths are compared after
// resolving symbolic links, `.` and `..`; empty paths are skipped.
void RefuseOutputOverInputs(const std::filesystem::path& output, const std::string& output_flag,
                            const std::vector<NamedInput>& inputs);

}  // namespace pipescope
