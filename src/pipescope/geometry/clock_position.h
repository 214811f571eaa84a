#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>

namespace pipescope {

// Clock positions, the inspection convention of GUIDE §4 (as NASSCO PACP and EN 13508-2 record
// them): looking along the direction of travel, 12 o'clock is the top of the pipe and 3 o'clock
// lies to the right. `up` is any vector that points to the top; only its part across the pipe
// counts.

// The clock angle in degrees, [0, 360), of `radial` (a direction from the pipe's axis towards
// the wall; its part along the axis is ignored) for travel along the unit vector `travel`: 0 at
// 12 o'clock, 90 at 3 o'clock. Unset when `up` or `radial` is (nearly) parallel to the axis,
// where no clock position is defined (a vertical pipe with a vertical `up`).
std::optional<double> ClockAngleDeg(const Eigen::Vector3d& radial, const Eigen::Vector3d& travel,
                                    const Eigen::Vector3d& up);

// A clock angle as the clock face reads it, "h:mm" to the nearest minute of the clock (0.5
// degrees): 0 -> "12:00", 90 -> "3:00", 345 -> "11:30".
std::string ClockString(double angle_deg);

// The camera's upright in the world, -y of the OpenCV camera frame (GUIDE §3), for
// `world_from_cam_rotation`.
Eigen::Vector3d CameraUpright(const Eigen::Matrix3d& world_from_cam_rotation);

}  // namespace pipescope
