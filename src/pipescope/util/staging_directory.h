#pragma once

#include <filesystem>
#include <string>

namespace pipescope {

// Writes a whole output folder atomically: everything goes into a hidden sibling of `target`,
// which Commit() renames onto `target`. A run that fails or is interrupted before Commit()
// leaves `target` as it was (the destructor removes the staging folder).
class StagingDirectory {
 public:
  // `flag` names the option that gave `target`, for error messages. An existing `target` must
  // be empty or hold `marker_file` (an earlier output of the same command), else InputError.
  StagingDirectory(std::filesystem::path target, std::string flag, std::string marker_file);
  ~StagingDirectory();
  StagingDirectory(const StagingDirectory&) = delete;
  StagingDirectory& operator=(const StagingDirectory&) = delete;

  const std::filesystem::path& path() const { return staging_; }

  // Moves the finished folder into place; an earlier `target` is removed only once the new one
  // is whole.
  void Commit();

 private:
  std::filesystem::path target_;
  std::filesystem::path staging_;
  bool committed_ = false;
};

}  // namespace pipescope
