#include "pipescope/cli/method_choice.h"

#include <fmt/format.h>

#include "pipescope/estimation/wall_distance_observability.h"
#include "pipescope/geometry/camera_mount.h"
#include "pipescope/image/undistortion.h"
#include "pipescope/pipeline/wall_distance_statement.h"
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
    return {"ekf",
            fmt::format("a {:.0f}-degree lens looks down the pipe: the tubular EKF (004); "
                        "`pipescope map` maps networks with it (001)",
                        2.0 * half_angle),
            ""};
  }
  if (!manifest.inner_radius_m) {
    throw InputError(ManifestName(manifest) +
                     ": pipe.inner_radius_m is missing, so no method can be chosen for this "
                     "wall camera: give --radius, or --method");
  }
  const double radius = *manifest.inner_radius_m;
  const bool has_reference_scale =
      manifest.reference_scale_px_per_m && *manifest.reference_scale_px_per_m > 0.0;
  const WallDistanceObservability view = AssessWallDistanceObservability(
      camera,
      MountedStartPose(CameraMount{}, radius, NominalStartWallDistance(manifest, camera, radius)),
      radius);
  if (view.observable) {
    // docs/conditions.md: on the 6-inch pipe the filter follows the wander (legs within
    // 0.08 %) and keeps its legs under the sheen (0.25 %), where sparse reaches 0.47 %; both
    // lose weak, noisy texture and say so, where dense-unrolled stays within 0.2 %.
    return {
        "ekf",
        fmt::format("this wall view sees the wall's curvature ({:.2f} % of scale per pair of "
                    "views), so the tubular EKF (004) measures the camera's place in the pipe "
                    "instead of assuming it; the best over the conditions matrix for such views",
                    view.scale_sigma_pct),
        has_reference_scale ? kNarrowViewMethod : "sparse"};
  }
  if (!has_reference_scale) {
    return {"sparse",
            fmt::format("this wall view cannot measure the wall distance ({:.2f} % of scale per "
                        "pair of views) and the dense methods need reference_scale_px_per_m, "
                        "which the dataset lacks: sparse, taking the camera to be on the pipe's "
                        "axis",
                        view.scale_sigma_pct),
            ""};
  }
  return {kNarrowViewMethod,
          fmt::format("this wall view cannot measure the wall distance ({:.2f} % of scale per pair "
                      "of views): {}, the best over the conditions matrix for narrow views "
                      "(docs/conditions.md)",
                      view.scale_sigma_pct, kNarrowViewMethod),
          ""};
}

}  // namespace pipescope
