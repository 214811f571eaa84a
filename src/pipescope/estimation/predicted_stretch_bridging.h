#pragma once

#include <cstddef>
#include <vector>

#include "pipescope/io/trajectory.h"

namespace pipescope {

// What an incremental odometer knows of each frame, for BridgePredictedStretches().
struct FrameMeasurement {
  bool predicted = false;   // the registration failed; the pose continued the recent motion
  bool became_key = false;  // later frames were registered to this frame
};

// Issue 22: a stretch of frames whose registration failed is not extrapolated as if it had been
// measured. When measured frames enclose the stretch and none of its frames became the key frame
// (so the frame after it was registered to the same key as the frame before it, and both poses
// are measurements), the stretch's poses are replaced by interpolation between the two: position
// linear in time, rotation by slerp. Stretches at the end of the run, or that a predicted key
// frame carried into later poses, are left as they are. `trajectory` and `frames` are in frame
// order, one entry per frame. Returns the indices of the frames bridged.
std::vector<std::size_t> BridgePredictedStretches(const std::vector<FrameMeasurement>& frames,
                                                  Trajectory* trajectory);

}  // namespace pipescope
