#pragma once

#include <string>
#include <vector>

#include "pipescope/pipeline/loop_closure_pass.h"
#include "pipescope/pipeline/t_intersection_pass.h"

namespace pipescope {

// Whether anything beyond the T model confirms the angle of a map run's turns. The T model
// (001 §III-D) is the only measurement of a turn's angle, and on the simulated networks it
// erred by up to 12.6 degrees with template matching while every straight side held within
// 0.51 %: a run through one turn ended 4.3 % off its true end point. With the features followed
// (the default since the fifteenth session) eight Ts came within 1.2 degrees, yet route A's
// T1-T4, three turns apart, was 2.0 % off: the straight pipes' heading drifts between the Ts
// (docs/fisheye_mapping.md). A turn is confirmed when it
// lies inside a closed loop whose junction the run placed again where it had been (the revisit's
// passages within `max_gap_share` of the path between them, after the closure if one was
// applied): the loop's turns then agree with each other. Every other turn leaves the positions
// past it unconfirmed, while the distances along each pipe do not depend on it.
//
// `junction_names` runs beside `t_intersections` (the name in junctions.yaml, empty for a T that
// placed no centre). Returns one reason per unconfirmed turn, for run.json's quality block; a T
// passed straight through (rejection "no turn") is no turn.
//
// A T adjusted with its angle held at the user's fitting angle (record.phi_given,
// t_fitting_angle_deg) rests on that angle, not on the images, and is still a reason outside a
// held loop: the angle is the user's word, and the heading of the straight pipes on either side
// drifts too (route A's 26 000 frames with every T held at 90: T1-T4 4.4 % off, its orientation
// RMS 8.4 deg). The reason says so, and says whether the end cylinders' own angle (the model's
// start, record.initial_model) lies more than kMaxFittingAngleDisagreementDeg from the held one:
// then the fitting may not be what the user said.
std::vector<std::string> UnconfirmedTurnReasons(
    const std::vector<TIntersectionRecord>& t_intersections,
    const std::vector<std::string>& junction_names, const LoopClosureRecord& loop_closure,
    double max_gap_share = 0.01);

// The end cylinders' angle erred by up to 17.2 degrees on the simulated networks' Ts (84.9-107.2
// for 89.6-90 over seven runs); a 45-degree wye taken for a tee is 45 off.
constexpr double kMaxFittingAngleDisagreementDeg = 20.0;

}  // namespace pipescope
