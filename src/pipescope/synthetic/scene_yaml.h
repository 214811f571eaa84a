#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <optional>

#include "pipescope/synthetic/scene.h"

namespace pipescope {

// Writes the scene's geometry as scene.yaml (issue 3), atomically, numbers in full precision:
//   radius: the first section's radius
//   sections: in route order (Scene::entries()), each with `type`:
//     straight: start, end ([x, y, z] metres), radius
//     bend: start, end, center (bend centre), axis (unit bend-plane normal; the turn is
//           right-handed about it), bend_radius, angle_deg, radius
//     tee: name, center
//   junctions: list of {name, center}, as io/junctions.h ReadSceneJunctions reads them.
//   route_start: {position, heading}, when given: where the run starts on its route and the
//     unit direction it drives (loop closure counts the turns from there,
//     pipeline/pipe_plan_yaml.h).
// Throws std::invalid_argument for a scene without sections.
struct RouteStart {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d heading = Eigen::Vector3d::UnitZ();
};
void WriteSceneYaml(const std::filesystem::path& path, const Scene& scene,
                    const std::optional<RouteStart>& route_start = std::nullopt);

}  // namespace pipescope
