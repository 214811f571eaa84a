#pragma once

#include <cmath>

#include "pipescope/camera/camera.h"

namespace pipescope {

struct KannalaBrandtFitOptions {
  // Largest angle from the optical axis that is fitted, radians. Kannala-Brandt as OpenCV and
  // COLMAP (OPENCV_FISHEYE) evaluate it projects through x/z, so it cannot hold rays at or
  // beyond 90 degrees; 85 degrees keeps the fit clear of the pole of tan(theta).
  double max_angle = 85.0 * M_PI / 180.0;
  // Directions sampled: angles evenly spaced in (0, max_angle], times azimuths around the axis.
  int num_angles = 200;
  int num_azimuths = 16;
};

struct KannalaBrandtFit {
  Camera camera;      // kannala-brandt, the source's image size.
  double rms_px = 0;  // Pixel distance to the source's projection over the sampled directions.
  double max_px = 0;
  int num_samples = 0;  // Directions that the source camera projects.
};

// Least-squares Kannala-Brandt (fx, fy, cx, cy, k1..k4) whose projections match `source`'s over
// directions up to options.max_angle: what a tool that only knows OpenCV's fisheye model (e.g.
// COLMAP) is given for a fisheye-poly camera. Throws std::invalid_argument for options outside
// (0, pi/2) or fewer than 8 samples.
KannalaBrandtFit FitKannalaBrandt(const Camera& source,
                                  const KannalaBrandtFitOptions& options = {});

}  // namespace pipescope
