#include "pipescope/util/staging_directory.h"

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>

#include "pipescope/util/error.h"

namespace pipescope {
namespace {

std::filesystem::path Sibling(const std::filesystem::path& target, const std::string& tag,
                              pid_t pid = getpid()) {
  const std::filesystem::path parent = target.has_parent_path() ? target.parent_path() : ".";
  return parent / ("." + target.filename().string() + "." + tag + "-" + std::to_string(pid));
}

// Staging folders left by runs that were killed (their process is gone) are removed, so an
// interrupted multi-gigabyte render does not stay on disk for ever.
void RemoveAbandonedStaging(const std::filesystem::path& target) {
  const std::filesystem::path parent = target.has_parent_path() ? target.parent_path() : ".";
  const std::string prefix = "." + target.filename().string() + ".partial-";
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(parent, error)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(prefix, 0) != 0) continue;
    const pid_t pid = static_cast<pid_t>(std::atol(name.c_str() + prefix.size()));
    if (pid > 0 && kill(pid, 0) != 0 && errno == ESRCH) {
      std::filesystem::remove_all(entry.path(), error);
    }
  }
}

}  // namespace

StagingDirectory::StagingDirectory(std::filesystem::path target, std::string flag,
                                   std::string marker_file)
    : target_(std::move(target)) {
  if (target_.filename().empty()) target_ = target_.parent_path();  // "out/" -> "out"
  if (std::filesystem::exists(target_)) {
    if (!std::filesystem::is_directory(target_)) {
      throw InputError(flag + " " + target_.string() + " exists and is not a folder");
    }
    if (!std::filesystem::is_empty(target_) && !std::filesystem::exists(target_ / marker_file)) {
      throw InputError(flag + " " + target_.string() + " is a non-empty folder without " +
                       marker_file + "; refusing to replace it");
    }
  }
  RemoveAbandonedStaging(target_);
  staging_ = Sibling(target_, "partial");
  std::error_code error;
  std::filesystem::remove_all(staging_, error);
  std::filesystem::create_directories(staging_, error);
  if (error) {
    throw InputError(flag + ": cannot create " + staging_.string() + ": " + error.message());
  }
}

StagingDirectory::~StagingDirectory() {
  if (committed_) return;
  std::error_code ignored;
  std::filesystem::remove_all(staging_, ignored);
}

void StagingDirectory::Commit() {
  std::filesystem::path previous;
  if (std::filesystem::exists(target_)) {
    previous = Sibling(target_, "old");
    std::filesystem::rename(target_, previous);
  }
  try {
    std::filesystem::rename(staging_, target_);
  } catch (...) {
    // Put the earlier output back rather than leave neither in place.
    std::error_code ignored;
    if (!previous.empty()) std::filesystem::rename(previous, target_, ignored);
    throw;
  }
  committed_ = true;
  if (!previous.empty()) std::filesystem::remove_all(previous);
}

}  // namespace pipescope
