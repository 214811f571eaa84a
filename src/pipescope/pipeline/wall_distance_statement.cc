#include "pipescope/pipeline/wall_distance_statement.h"

#include <fmt/format.h>

#include <algorithm>
#include <utility>

#include "pipescope/image/undistortion.h"
#include "pipescope/util/error.h"

namespace pipescope {

double NominalStartWallDistance(const DatasetManifest& manifest, const Camera& camera,
                                double radius_m) {
  if (!manifest.reference_scale_px_per_m || !(*manifest.reference_scale_px_per_m > 0.0)) {
    return radius_m;
  }
  const double start_m = CentralFocalLengthPx(camera) / *manifest.reference_scale_px_per_m;
  return start_m < 2.0 * radius_m ? start_m : radius_m;
}

WallDistanceStatement MakeWallDistanceStatement(const Camera& camera, const CameraMount& mount,
                                                double radius_m, double start_m,
                                                std::string start_from, bool method_measures) {
  WallDistanceStatement statement;
  statement.start_m = start_m;
  statement.start_from = std::move(start_from);
  statement.method_measures = method_measures;
  if (radius_m > 0.0) {
    try {
      statement.observability = AssessWallDistanceObservability(
          camera, MountedStartPose(mount, radius_m, start_m), radius_m);
    } catch (const InputError&) {
      // A set-up the assessment cannot judge (too little of the wall in view): unknown, said so
      // in run.json (view_observes: null); the run itself goes on.
    }
  }
  return statement;
}

double CrossSectionExcursion(const Trajectory& poses) {
  double excursion = 0.0;
  for (const StampedPose& pose : poses) {
    excursion = std::max(excursion, (pose.position - poses.front().position).head<2>().norm());
  }
  return excursion;
}

std::string UnobservedExcursionReason(const WallDistanceStatement& statement, double excursion_m,
                                      double limit_share) {
  const double share = excursion_m / statement.start_m;
  if (WallDistanceMeasured(statement) || !(limit_share > 0.0) || share <= limit_share) return "";
  return fmt::format(
      "this view cannot measure the camera's distance to the wall, and the estimated camera "
      "strays {:.1f} mm across the pipe ({:.1f} % of that distance; limit {:.1f} %): the scale "
      "follows an excursion the images could not confirm",
      1000.0 * excursion_m, 100.0 * share, 100.0 * limit_share);
}

bool WallDistanceMeasured(const WallDistanceStatement& statement) {
  return statement.method_measures && statement.observability &&
         statement.observability->observable;
}

nlohmann::json WallDistanceJson(const WallDistanceStatement& statement) {
  nlohmann::json json = {
      {"measured", WallDistanceMeasured(statement)},
      {"method_measures", statement.method_measures},
      {"start_m", statement.start_m},
      {"start_from", statement.start_from},
      // A stretch driven 1 mm nearer the wall than assumed reads this much long.
      {"scale_error_pct_per_mm", 0.1 / statement.start_m},
      {"view_observes", nullptr},
  };
  if (const auto& o = statement.observability) {
    json["view_observes"] = o->observable;
    json["observability"] = {{"step_m", o->step_m},
                             {"pixels", o->pixels},
                             {"parallax_px_per_mm", o->parallax_px_per_mm},
                             {"wall_distance_sigma_mm", o->wall_distance_sigma_mm},
                             {"scale_sigma_pct", o->scale_sigma_pct}};
  }
  return json;
}

std::string WallDistanceWarning(const WallDistanceStatement& statement, const std::string& method) {
  if (WallDistanceMeasured(statement)) return "";
  const std::string cost = fmt::format(
      "a stretch driven 1 mm nearer the wall than that reads {:.2f} % long (wall_distance in "
      "run.json)",
      0.1 / statement.start_m);
  const std::string held =
      fmt::format("the start's {:.1f} mm ({})", 1000.0 * statement.start_m, statement.start_from);
  const auto& o = statement.observability;
  if (statement.method_measures && !o) {
    return fmt::format(
        "{}: whether this view can measure the camera's distance to the wall is unknown; the "
        "scale holds {} on average: {}",
        method, held, cost);
  }
  if (statement.method_measures) {
    return fmt::format(
        "{}: this view sees too little of the wall's curvature to measure the camera's distance "
        "to the wall ({:.2f} % of scale per pair of views); the scale holds {} on average: {}",
        method, o->scale_sigma_pct, held, cost);
  }
  std::string view = "without the pipe's radius, whether this view could measure it is unknown";
  if (o) {
    view = o->observable
               ? fmt::format(
                     "this view sees the wall's curvature well enough to measure it ({:.2f} % "
                     "of scale per pair of views: --method ekf, sparse, or dense-unrolled "
                     "where the texture allows)",
                     o->scale_sigma_pct)
               : fmt::format(
                     "this view could not measure it either ({:.2f} % of scale per pair "
                     "of views)",
                     o->scale_sigma_pct);
  }
  return fmt::format("{} takes the camera's distance to the wall as fixed at {}: {}; {}", method,
                     held, cost, view);
}

}  // namespace pipescope
