#include "pipescope/util/atomic_file.h"

#include <unistd.h>

#include <atomic>
#include <fstream>
#include <sstream>

#include "pipescope/util/error.h"

namespace pipescope {
namespace {

std::filesystem::path TemporaryPathFor(const std::filesystem::path& path) {
  static std::atomic<int> counter{0};
  // Keep the extension last so writers that choose a format by extension (cv::imwrite) work.
  std::filesystem::path temporary = path;
  temporary.replace_filename("." + path.stem().string() + ".tmp" + std::to_string(getpid()) + "_" +
                             std::to_string(counter++) + path.extension().string());
  return temporary;
}

}  // namespace

void WriteFileAtomically(
    const std::filesystem::path& path,
    const std::function<void(const std::filesystem::path&)>& write_to_temporary) {
  const std::filesystem::path parent = path.has_parent_path() ? path.parent_path() : ".";
  std::error_code error;
  std::filesystem::create_directories(parent, error);
  if (error) {
    throw InputError("cannot create directory " + parent.string() + ": " + error.message());
  }
  const std::filesystem::path temporary = TemporaryPathFor(path);
  try {
    write_to_temporary(temporary);
    std::filesystem::rename(temporary, path);
  } catch (...) {
    std::filesystem::remove(temporary, error);
    throw;
  }
}

void WriteTextFileAtomically(const std::filesystem::path& path, const std::string& contents) {
  WriteFileAtomically(path, [&](const std::filesystem::path& temporary) {
    std::ofstream stream(temporary, std::ios::binary);
    stream << contents;
    stream.close();
    if (!stream) throw InputError("cannot write " + path.string());
  });
}

std::string ReadTextFile(const std::filesystem::path& path) {
  std::ifstream stream(path, std::ios::binary);
  if (!stream) throw InputError("cannot read " + path.string());
  std::ostringstream buffer;
  buffer << stream.rdbuf();
  return buffer.str();
}

}  // namespace pipescope
