#pragma once

#include <filesystem>
#include <functional>
#include <string>

namespace pipescope {

// Writes `path` through `write_to_temporary`, which receives a temporary path in the same
// directory; the temporary is renamed onto `path` only when the writer returns normally, so a
// reader never sees a half-written file. On failure the temporary is removed and the error
// rethrown.
void WriteFileAtomically(
    const std::filesystem::path& path,
    const std::function<void(const std::filesystem::path&)>& write_to_temporary);

// Writes `contents` to `path` atomically.
void WriteTextFileAtomically(const std::filesystem::path& path, const std::string& contents);

// Reads a whole text file; throws InputError naming the file when it cannot be read.
std::string ReadTextFile(const std::filesystem::path& path);

}  // namespace pipescope
