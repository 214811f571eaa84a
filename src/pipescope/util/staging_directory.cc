#include "pipescope/util/staging_directory.h"

#include <unistd.h>

#include "pipescope/util/error.h"

namespace pipescope {
namespace {

std::filesystem::path Sibling(const std::filesystem::path& target, const std::string& tag) {
  const std::filesystem::path parent = target.has_parent_path() ? target.parent_path() : ".";
  return parent / ("." + target.filename().string() + "." + tag + "-" + std::to_string(getpid()));
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
  std::filesystem::rename(staging_, target_);
  committed_ = true;
  if (!previous.empty()) std::filesystem::remove_all(previous);
}

}  // namespace pipescope
