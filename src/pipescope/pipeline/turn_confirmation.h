#pragma once

#include <string>
#include <vector>

#include "pipescope/pipeline/loop_closure_pass.h"
#include "pipescope/pipeline/t_intersection_pass.h"

namespace pipescope {

// Whether anything beyond the T model confirms the angle of a map run's turns. The T model
// (001 §III-D) is the only measurement of a turn's angle, and on the simulated networks it
// erred by up to 12.6 degrees while every straight side held within 0.51 %: a run through one
// turn ended 4.3 % off its true end point (docs/fisheye_mapping.md). A turn is confirmed when it
// lies inside a closed loop whose junction the run placed again where it had been (the revisit's
// passages within `max_gap_share` of the path between them, after the closure if one was
// applied): the loop's turns then agree with each other. Every other turn leaves the positions
// past it unconfirmed, while the distances along each pipe do not depend on it.
//
// `junction_names` runs beside `t_intersections` (the name in junctions.yaml, empty for a T that
// placed no centre). Returns one reason per unconfirmed turn, for run.json's quality block; a T
// passed straight through (rejection "no turn") is no turn.
std::vector<std::string> UnconfirmedTurnReasons(
    const std::vector<TIntersectionRecord>& t_intersections,
    const std::vector<std::string>& junction_names, const LoopClosureRecord& loop_closure,
    double max_gap_share = 0.01);

}  // namespace pipescope
