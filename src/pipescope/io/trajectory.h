#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <filesystem>
#include <vector>

namespace pipescope {

// One pose of a trajectory: world_from_cam (camera-to-world), as in the TUM format (GUIDE §3).
struct StampedPose {
  double timestamp = 0;
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
};

using Trajectory = std::vector<StampedPose>;

// A world_from_cam transform as a stamped pose, and back.
StampedPose ToStampedPose(double timestamp, const Eigen::Isometry3d& world_from_cam);
Eigen::Isometry3d ToIsometry(const StampedPose& pose);

// Reads a TUM trajectory: one pose a line, `timestamp tx ty tz qx qy qz qw`; `#` comments and
// blank lines are skipped. Quaternions are normalised. The order of the file is kept, but
// timestamps must not decrease. Throws InputError naming the file and line for a malformed line,
// a non-finite number, a zero quaternion or a decreasing timestamp, and for a file without poses.
Trajectory ReadTumTrajectory(const std::filesystem::path& path);

// Writes `trajectory` as TUM text, atomically, with a header comment. Times are written with
// nanosecond resolution and values with 17 significant digits, so reading back is lossless.
void WriteTumTrajectory(const std::filesystem::path& path, const Trajectory& trajectory);

}  // namespace pipescope
