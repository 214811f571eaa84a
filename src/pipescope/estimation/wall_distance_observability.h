#pragma once

#include <Eigen/Geometry>

#include "pipescope/camera/camera.h"

namespace pipescope {

// How well a camera's images fix its distance to the wall of a straight pipe of known radius
// (beyond 000). On a flat wall that distance is monocular scale and cannot be seen; a cylinder's
// curvature across the view is what tells a camera 1 mm nearer the wall from a shorter step.
// Measured for the set-up before any frame is read: one step along the pipe seen by a grid of
// pixels, compared with the same step from a camera 1 mm nearer the wall, after every other
// motion of the second view (its step, its own change of wall distance, sideways shift, roll,
// pan and tilt) has mimicked as much of the difference as it can. What is left is the signal.
struct WallDistanceObservability {
  double step_m = 0.0;  // the step used: a third of the view's extent on the wall
  int pixels = 0;       // grid pixels whose rays meet the wall in both views
  // RMS over those pixels of the image motion no other motion can mimic, per mm nearer the wall.
  double parallax_px_per_mm = 0.0;
  // The wall distance one pair of views fixes (1 sigma) from `features` points localised to
  // `pixel_sigma_px` each: pixel_sigma_px / (parallax_px_per_mm * sqrt(features)).
  double wall_distance_sigma_mm = 0.0;
  // The same as a share of the wall distance: the scale error of a stretch whose wall distance
  // is off by that much, percent.
  double scale_sigma_pct = 0.0;
  bool observable = false;  // scale_sigma_pct <= max_scale_sigma_pct
};

struct WallDistanceObservabilityOptions {
  int grid = 15;                // grid x grid pixels, inset 5 % from the border
  int features = 200;           // tracked points per pair of views
  double pixel_sigma_px = 0.3;  // their localisation
  // The largest scale uncertainty per pair that still counts as seeing the wall distance.
  double max_scale_sigma_pct = 0.5;
};

// `start_world_from_cam`: the camera in the pipe frame (axis Z, centre at the origin), facing the
// wall. Throws InputError when fewer than 12 grid pixels see the wall in both views.
WallDistanceObservability AssessWallDistanceObservability(
    const Camera& camera, const Eigen::Isometry3d& start_world_from_cam, double radius_m,
    const WallDistanceObservabilityOptions& options = {});

}  // namespace pipescope
