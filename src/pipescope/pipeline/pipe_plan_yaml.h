#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <string>

#include "pipescope/estimation/pipe_network_plan.h"

namespace pipescope {

// The plan of a pipe network in a scene.yaml (GUIDE §4; docs/formats.md): `sections` of type
// `straight` (start, end, radius or the file's `radius`) and `tee` (name, center), and
// `route_start: {position: [x, y, z], heading: [x, y, z]}`, where the run started and which way
// it drove. `up` is the dataset's pipe.up, in the same frame. Returns nullopt with `*why_not`
// when the file holds no plan loop closure can use (no route_start, a bend, no tee); throws
// InputError naming the file and key when a value is malformed.
std::optional<PipePlan> ReadPipePlan(const std::filesystem::path& scene_yaml,
                                     const Eigen::Vector3d& up, std::string* why_not);

}  // namespace pipescope
