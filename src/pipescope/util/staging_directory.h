#pragma once

#include <filesystem>
#include <string>

#include "pipescope/util/interruption.h"

namespace pipescope {

// Writes a whole output folder atomically: everything goes into a hidden sibling of `target`,
// `.NAME.partial-PID`, which Commit() puts in place of `target`.
// - A run that fails before Commit() leaves `target` as it was (the destructor removes the
//   staging folder); SIGINT/SIGTERM remove it too (util/interruption.h).
// - Commit() swaps the two folders in one atomic rename (renameat2 RENAME_EXCHANGE; ext4, xfs,
//   btrfs and tmpfs have it), so at every instant either the old or the new output exists
//   whole. On a file system without it, the old output is first renamed to `.NAME.old-PID`; a
//   kill between the two renames leaves it there, and the next run into the same parent puts
//   it back.
// - Staging folders of killed processes (SIGKILL, power loss) are removed by the next run into
//   the same parent.
class StagingDirectory {
 public:
  // `flag` names the option that gave `target`, for error messages. An existing `target` must
  // be empty or hold `marker_file` (an earlier output of the same command), else InputError;
  // so must a target that is the working directory or holds it.
  StagingDirectory(std::filesystem::path target, std::string flag, std::string marker_file);
  ~StagingDirectory();
  StagingDirectory(const StagingDirectory&) = delete;
  StagingDirectory& operator=(const StagingDirectory&) = delete;

  const std::filesystem::path& path() const { return staging_; }
  // Where Commit() puts the folder.
  const std::filesystem::path& target() const { return target_; }

  // Moves the finished folder into place; an earlier `target` is removed only once the new one
  // is whole.
  void Commit();

 private:
  std::filesystem::path target_;
  std::filesystem::path staging_;
  RemoveOnInterruption remove_on_interruption_;
  bool committed_ = false;
};

// Removes the hidden folders beside `target` that processes which no longer run left behind:
// `.NAME.partial-PID` (a run killed while writing) and `.NAME.old-PID` (a run killed between
// the two renames of a replacement; put back in place when `target` is missing).
void RemoveAbandonedStaging(const std::filesystem::path& target);

}  // namespace pipescope
