#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace pipescope::fuzz {

// A folder of this process's own under the system's temporary folder: the parsers take paths,
// and fuzzers of other targets may run at the same time.
inline const std::filesystem::path& FuzzDirectory() {
  static const std::filesystem::path dir = [] {
    const std::filesystem::path made =
        std::filesystem::temp_directory_path() / ("pipescope_fuzz_" + std::to_string(::getpid()));
    std::filesystem::create_directories(made);
    return made;
  }();
  return dir;
}

// Writes the fuzzer's input to `name` in FuzzDirectory() and returns its path.
inline std::filesystem::path WriteFuzzInput(const std::uint8_t* data, std::size_t size,
                                            const std::string& name) {
  const std::filesystem::path path = FuzzDirectory() / name;
  std::ofstream stream(path, std::ios::binary | std::ios::trunc);
  stream.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

}  // namespace pipescope::fuzz
