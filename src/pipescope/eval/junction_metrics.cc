#include "pipescope/eval/junction_metrics.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "pipescope/util/error.h"

namespace pipescope {

Eigen::Vector3d InterpolatePosition(const Trajectory& ground_truth, double t) {
  const auto after =
      std::lower_bound(ground_truth.begin(), ground_truth.end(), t,
                       [](const StampedPose& pose, double time) { return pose.timestamp < time; });
  if (after == ground_truth.begin()) return ground_truth.front().position;
  if (after == ground_truth.end()) return ground_truth.back().position;
  const StampedPose& p0 = *(after - 1);
  const StampedPose& p1 = *after;
  const double span = p1.timestamp - p0.timestamp;
  const double w = span > 0 ? (t - p0.timestamp) / span : 1.0;
  return (1 - w) * p0.position + w * p1.position;
}

std::vector<JunctionDistance> EvaluateJunctionDistances(
    const Trajectory& ground_truth, const std::vector<Junction>& scene_junctions,
    const std::vector<Junction>& estimated_junctions) {
  if (estimated_junctions.empty()) return {};
  if (ground_truth.empty()) throw InputError("--gt: no poses to place the junctions");
  if (scene_junctions.empty()) throw InputError("--scene: no junctions to match");

  struct Match {
    std::size_t estimated;
    std::size_t scene;
    double distance_m;  // From the ground-truth camera to the scene junction.
  };
  std::vector<Match> matches;
  std::map<std::size_t, std::size_t> match_of_scene;  // scene index -> index into matches.
  for (std::size_t i = 0; i < estimated_junctions.size(); ++i) {
    const Junction& estimated = estimated_junctions[i];
    if (!std::isfinite(estimated.timestamp)) {
      throw InputError("--junctions: junction '" + estimated.name + "' has no timestamp");
    }
    // The camera passes through a junction's centre, so ground truth at that time tells which
    // junction the estimate refers to, whatever the estimate's own drift.
    const Eigen::Vector3d camera = InterpolatePosition(ground_truth, estimated.timestamp);
    Match match{i, 0, std::numeric_limits<double>::infinity()};
    for (std::size_t s = 0; s < scene_junctions.size(); ++s) {
      const double distance = (scene_junctions[s].center - camera).norm();
      if (distance < match.distance_m) {
        match.distance_m = distance;
        match.scene = s;
      }
    }
    const auto [it, inserted] = match_of_scene.emplace(match.scene, matches.size());
    if (inserted) {
      matches.push_back(match);
      continue;
    }
    Match& previous = matches[it->second];
    spdlog::warn("junctions '{}' and '{}' both match scene junction '{}'; keeping the closer",
                 estimated_junctions[previous.estimated].name, estimated.name,
                 scene_junctions[match.scene].name);
    if (match.distance_m < previous.distance_m) previous = match;
  }
  // Replacing a match keeps its slot; restore the order of the estimated junctions.
  std::sort(matches.begin(), matches.end(),
            [](const Match& a, const Match& b) { return a.estimated < b.estimated; });

  std::vector<JunctionDistance> distances;
  for (std::size_t i = 0; i < matches.size(); ++i) {
    for (std::size_t j = i + 1; j < matches.size(); ++j) {
      const Junction& scene_i = scene_junctions[matches[i].scene];
      const Junction& scene_j = scene_junctions[matches[j].scene];
      JunctionDistance distance;
      distance.from = scene_i.name;
      distance.to = scene_j.name;
      distance.gt_m = (scene_i.center - scene_j.center).norm();
      distance.est_m = (estimated_junctions[matches[i].estimated].center -
                        estimated_junctions[matches[j].estimated].center)
                           .norm();
      distance.error_m = distance.est_m - distance.gt_m;
      // 001 Table I reports the error relative to the true distance.
      distance.error_pct = distance.gt_m > 0 ? 100.0 * std::abs(distance.error_m) / distance.gt_m
                                             : std::numeric_limits<double>::quiet_NaN();
      distances.push_back(distance);
    }
  }
  return distances;
}

}  // namespace pipescope
