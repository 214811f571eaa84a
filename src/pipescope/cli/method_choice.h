#pragma once

#include <string>

#include "pipescope/camera/camera.h"
#include "pipescope/io/dataset.h"

namespace pipescope {

// The odometry method for a run given no --method (issue 22): the one the conditions matrix
// (bench/conditions.sh, docs/conditions.md) shows best for the dataset's set-up, and why.
struct MethodChoice {
  std::string method;
  std::string reason;
  // Run when `method` fails or ends unreliable (texture too weak to track); empty: none.
  std::string fallback;
};

// Wide-angle cameras (a half angle beyond 80 degrees: fisheyes looking down the pipe) get the
// tubular EKF; wall cameras get it too where their view sees the wall's curvature well enough to
// measure the wall distance (WallDistanceObservability), falling back to `kNarrowViewMethod` (with
// a reference scale) or `sparse` when its run is unreliable, and `kNarrowViewMethod` where it does
// not. Throws InputError when the dataset lacks what every candidate needs.
MethodChoice ChooseOdometryMethod(const DatasetManifest& manifest, const Camera& camera);

}  // namespace pipescope
