#include "pipescope/util/atomic_file.h"

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "pipescope/util/error.h"
#include "pipescope/util/interruption.h"

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

// Temporaries of `path` whose writer was killed (SIGKILL, power loss) are removed by the next
// write of the same file.
void RemoveAbandonedTemporaries(const std::filesystem::path& path) {
  const std::string prefix = "." + path.stem().string() + ".tmp";
  const std::filesystem::path parent = path.has_parent_path() ? path.parent_path() : ".";
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(parent, error)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(prefix, 0) != 0 || entry.path().extension() != path.extension()) continue;
    const pid_t pid = static_cast<pid_t>(std::atol(name.c_str() + prefix.size()));
    if (pid > 0 && kill(pid, 0) != 0 && errno == ESRCH) {
      std::filesystem::remove(entry.path(), error);
    }
  }
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
  RemoveAbandonedTemporaries(path);
  const std::filesystem::path temporary = TemporaryPathFor(path);
  RemoveOnInterruption remove_on_interruption(temporary);
  try {
    write_to_temporary(temporary);
    WithoutInterruption([&] {
      std::filesystem::rename(temporary, path);
      remove_on_interruption.Release();
    });
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
