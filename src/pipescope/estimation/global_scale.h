#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "pipescope/camera/camera.h"
#include "pipescope/estimation/window_adjustment.h"

namespace pipescope {

// Beyond 000: one correction for the whole run of the camera's place in the cross-section, and
// with it the scale. With a narrow lens the wall distance is seen only through the wall's slight
// curvature, so each window adjustment keeps the cross-section offset it inherits from the
// first one (measured: a constant 1.8 mm on steel-16in, 0.9 % of the travel). Here every key
// frame's position is moved by a common (dX, dY) and its travel from the first key frame scaled by
// s, rotations kept, so that every track's reprojection through the cylinder (eq. 47) over the
// whole run fits best: the curvature cue of all windows at once.
struct GlobalScaleOptions {
  double robust_loss_px = 1.0;
  int max_iterations = 20;
  // Use every k-th key frame as a reference of transfers (speed).
  int reference_stride = 1;
};

struct GlobalScaleResult {
  Eigen::Vector2d offset_xy = Eigen::Vector2d::Zero();
  double scale = 1.0;
  int residuals = 0;
  double initial_rms_px = 0.0;
  double final_rms_px = 0.0;
};

// `key_frames`: poses and keypoints (tracks) of the whole run; `fixed` is ignored. The poses are
// updated in place.
GlobalScaleResult CorrectGlobalScale(const Camera& camera, double radius_m,
                                     const GlobalScaleOptions& options,
                                     std::vector<WindowKeyFrame>* key_frames);

}  // namespace pipescope
