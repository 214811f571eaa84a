#pragma once

#include <filesystem>

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
// Throws std::invalid_argument for a scene without sections.
void WriteSceneYaml(const std::filesystem::path& path, const Scene& scene);

}  // namespace pipescope
