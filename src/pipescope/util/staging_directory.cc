#include "pipescope/util/staging_directory.h"

#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

#include "pipescope/util/error.h"

namespace pipescope {
namespace {

std::filesystem::path ParentOf(const std::filesystem::path& target) {
  return target.has_parent_path() ? target.parent_path() : ".";
}

std::filesystem::path Sibling(const std::filesystem::path& target, const std::string& tag,
                              pid_t pid = getpid()) {
  return ParentOf(target) /
         ("." + target.filename().string() + "." + tag + "-" + std::to_string(pid));
}

bool ProcessIsGone(pid_t pid) { return pid > 0 && kill(pid, 0) != 0 && errno == ESRCH; }

// The pid of a hidden sibling `.NAME.TAG-PID`, or 0 when `name` is not one.
pid_t SiblingPid(const std::string& name, const std::string& target_name, const std::string& tag) {
  const std::string prefix = "." + target_name + "." + tag + "-";
  if (name.rfind(prefix, 0) != 0) return 0;
  return static_cast<pid_t>(std::atol(name.c_str() + prefix.size()));
}

// True when `target` is the working directory or one of its parents: replacing it would pull
// the floor from under the process (and the user's shell).
bool HoldsWorkingDirectory(const std::filesystem::path& target) {
  std::error_code error;
  const std::filesystem::path cwd = std::filesystem::current_path(error);
  const std::filesystem::path full = std::filesystem::weakly_canonical(target, error);
  if (error) return false;
  auto cwd_part = cwd.begin();
  for (const auto& part : full) {
    if (part.empty()) continue;
    if (cwd_part == cwd.end() || *cwd_part != part) return false;
    ++cwd_part;
  }
  return true;
}

}  // namespace

void RemoveAbandonedStaging(const std::filesystem::path& target) {
  const std::string target_name = target.filename().string();
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(ParentOf(target), error)) {
    const std::string name = entry.path().filename().string();
    if (ProcessIsGone(SiblingPid(name, target_name, "partial"))) {
      std::filesystem::remove_all(entry.path(), error);
    } else if (ProcessIsGone(SiblingPid(name, target_name, "old"))) {
      if (!std::filesystem::exists(target)) {
        std::filesystem::rename(entry.path(), target, error);
      } else {
        std::filesystem::remove_all(entry.path(), error);
      }
    }
  }
}

StagingDirectory::StagingDirectory(std::filesystem::path target, std::string flag,
                                   std::string marker_file)
    : target_(std::move(target)),
      staging_(Sibling(target_.filename().empty() ? target_.parent_path() : target_, "partial")),
      remove_on_interruption_(staging_) {
  if (target_.filename().empty()) target_ = target_.parent_path();  // "out/" -> "out"
  if (target_.empty() || target_.filename() == "." || target_.filename() == ".." ||
      HoldsWorkingDirectory(target_)) {
    throw InputError(flag + " " + (target_.empty() ? std::string("\"\"") : target_.string()) +
                     " is the working directory or holds it; name a folder of its own");
  }
  RemoveAbandonedStaging(target_);
  if (std::filesystem::exists(target_)) {
    if (!std::filesystem::is_directory(target_)) {
      throw InputError(flag + " " + target_.string() + " exists and is not a folder");
    }
    if (!std::filesystem::is_empty(target_) && !std::filesystem::exists(target_ / marker_file)) {
      throw InputError(flag + " " + target_.string() + " is a non-empty folder without " +
                       marker_file + "; refusing to replace it");
    }
  }
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
  WithoutInterruption([&] {
    if (!std::filesystem::exists(target_)) {
      std::filesystem::rename(staging_, target_);
      return;
    }
    // One atomic swap: the staging path then holds the old output, removed below.
    if (renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, target_.c_str(), RENAME_EXCHANGE) == 0) {
      return;
    }
    if (errno != EINVAL && errno != ENOSYS && errno != ENOTSUP) {
      throw std::filesystem::filesystem_error("cannot replace " + target_.string(), staging_,
                                              target_,
                                              std::error_code(errno, std::generic_category()));
    }
    // Two renames; RemoveAbandonedStaging() repairs a kill between them.
    const std::filesystem::path previous = Sibling(target_, "old");
    std::filesystem::rename(target_, previous);
    try {
      std::filesystem::rename(staging_, target_);
    } catch (...) {
      std::error_code ignored;
      std::filesystem::rename(previous, target_, ignored);
      throw;
    }
    std::filesystem::rename(previous, staging_);
  });
  committed_ = true;
  // The staging path now holds the earlier output, if there was one.
  std::error_code ignored;
  std::filesystem::remove_all(staging_, ignored);
  remove_on_interruption_.Release();
}

}  // namespace pipescope
