#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "pipescope/camera/camera.h"

namespace pipescope {

// The batch optimisation of 000 §5.3.2: the camera's offset (C_X, C_Y) from the axis, which acts
// as the scale of the whole trajectory, and the axial positions delta_h_a of the first key
// frames, with the start rotation fixed (eq. 45-46), minimising the reprojection error of eq.
// 47-49 through the wall.
struct InitialPositionOptions {
  // Cauchy loss scale on the reprojection error (pixels); 0 = plain least squares (000).
  double robust_loss_px = 1.0;
  int max_iterations = 50;
};

struct KeyFrameKeypoint {
  long long track = -1;  // global index g
  Eigen::Vector2d pixel;
  Eigen::Vector3d bearing;  // unit, camera frame
};

struct InitialPositionResult {
  Eigen::Vector2d c_xy;
  std::vector<double> delta_h;  // one per key frame, the first held at its given value
  double initial_rms_px = 0.0;
  double final_rms_px = 0.0;
  int residuals = 0;
};

// `key_frames[a]` are the keypoints of key frame a; `delta_h[a]` the starting axial positions.
// Every ordered pair of key frames sharing a track gives one residual (eq. 47). Key frame 0's
// delta_h is held fixed (the origin of h).
InitialPositionResult OptimiseInitialPosition(
    const Camera& camera, const Eigen::Matrix3d& world_from_cam_rotation, double radius_m,
    const Eigen::Vector2d& c_xy, const std::vector<double>& delta_h,
    const std::vector<std::vector<KeyFrameKeypoint>>& key_frames,
    const InitialPositionOptions& options);

}  // namespace pipescope
