#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "pipescope/camera/camera.h"
#include "pipescope/geometry/pipe_cylinder.h"
#include "pipescope/report/stations.h"

namespace pipescope {

// Where a pixel of a frame lies on the pipe wall, in inspection coordinates (GUIDE §4).
struct WallLocation {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // on the wall, in the run's frame
  double distance_m = 0.0;                          // along the pipe from the run's start
  double clock_angle_deg = 0.0;  // 0 = 12 o'clock; NaN where the pipe runs along "up"
  std::string clock;             // "h:mm", empty where undefined
  int section = 0;               // straight section of the pipe (0 for a single straight pipe)
};

// The wall point that `pixel` of a frame shows, on the cylinder of `radius_m` about `axis` (in
// the run's frame): the camera's ray, through Camera::Unproject, meets the cylinder; its
// distance is the frame's station plus the point's offset along the axis (pointed the way of the
// survey), its clock angle that of the point around the axis, looking that way. Unset when the
// pixel has no ray (outside the lens's valid angle), the ray runs along the axis, or the camera is
// not inside the cylinder.
std::optional<WallLocation> LocateOnCylinder(const Camera& camera,
                                             const Eigen::Isometry3d& world_from_cam,
                                             const Station& station, const Eigen::Vector2d& pixel,
                                             double radius_m, const PipeAxis& axis,
                                             const Eigen::Vector3d& up);

// The shortest arc of the clock face holding every angle (degrees): {from, to} read clockwise,
// e.g. {330, 30} for a box across 12 o'clock. NaN angles are ignored; empty input gives NaNs.
std::pair<double, double> ClockSpan(const std::vector<double>& angles_deg);

}  // namespace pipescope
