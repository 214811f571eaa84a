#include "pipescope/cli/method_choice.h"

#include <fmt/format.h>

#include "pipescope/estimation/wall_distance_observability.h"
#include "pipescope/geometry/camera_mount.h"
#include "pipescope/image/undistortion.h"
#include "pipescope/util/error.h"

namespace pipescope {
namespace {

// docs/conditions.md: the narrow wall camera's best method over the matrix.
constexpr const char* kNarrowViewMethod = "dense-unrolled";
constexpr double kForwardCameraHalfAngleDeg = 80.0;

}  // namespace

MethodChoice ChooseOdometryMethod(const DatasetManifest& manifest, const Camera& camera) {
  const double half_angle = ImageHalfAngleDeg(camera);
  if (half_angle > kForwardCameraHalfAngleDeg) {
    return {"ekf", fmt::format("a {:.0f}-degree lens looks down the pipe: the tubular EKF (004); "
                               "`pipescope map` maps networks with it (001)",
                               2.0 * half_angle)};
  }
  if (!manifest.inner_radius_m) {
    throw InputError(ManifestName(manifest) +
                     ": pipe.inner_radius_m is missing, so no method can be chosen for this "
                     "wall camera: give --radius, or --method");
  }
  const double radius = *manifest.inner_radius_m;
  const bool has_reference_scale =
      manifest.reference_scale_px_per_m && *manifest.reference_scale_px_per_m > 0.0;
  double wall_distance = has_reference_scale
                             ? CentralFocalLengthPx(camera) / *manifest.reference_scale_px_per_m
                             : radius;
  if (!(wall_distance < 2.0 * radius)) wall_distance = radius;
  const WallDistanceObservability view = AssessWallDistanceObservability(
      camera, MountedStartPose(CameraMount{}, radius, wall_distance), radius);
  if (view.observable) {
    // docs/conditions.md: sparse follows the wander (6-inch legs 0.06 % against the dense
    // methods' 1.7 %) but loses weak, noisy texture, where dense-unrolled stays within 0.2 %.
    return {"sparse",
            fmt::format("this wall view sees the wall's curvature ({:.2f} % of scale per pair of "
                        "views), so sparse measures the crawler's distance to the wall instead of "
                        "assuming it",
                        view.scale_sigma_pct),
            has_reference_scale ? kNarrowViewMethod : ""};
  }
  if (!has_reference_scale) {
    return {"sparse",
            fmt::format("this wall view cannot measure the wall distance ({:.2f} % of scale per "
                        "pair of views) and the dense methods need reference_scale_px_per_m, "
                        "which the dataset lacks: sparse, taking the camera to be on the pipe's "
                        "axis",
                        view.scale_sigma_pct)};
  }
  return {kNarrowViewMethod,
          fmt::format("this wall view cannot measure the wall distance ({:.2f} % of scale per pair "
                      "of views): {}, the best over the conditions matrix for narrow views "
                      "(docs/conditions.md)",
                      view.scale_sigma_pct, kNarrowViewMethod)};
}

}  // namespace pipescope
