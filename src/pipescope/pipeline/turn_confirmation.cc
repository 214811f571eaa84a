#include "pipescope/pipeline/turn_confirmation.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace pipescope {
namespace {

// A closed loop whose revisit holds confirms the turns from its first passage up to, not
// including, its last: the last passage's own turn leads out of the loop.
bool InsideHeldLoop(int section, const LoopClosureRecord& loop_closure, double max_gap_share) {
  for (const JunctionRevisit& revisit : loop_closure.revisits) {
    if (revisit.t_sections.size() < 2 || !RevisitHolds(loop_closure, revisit, max_gap_share)) {
      continue;
    }
    const auto [first, last] =
        std::minmax_element(revisit.t_sections.begin(), revisit.t_sections.end());
    if (*first <= section && section < *last) return true;
  }
  return false;
}

}  // namespace

std::vector<std::string> UnconfirmedTurnReasons(
    const std::vector<TIntersectionRecord>& t_intersections,
    const std::vector<std::string>& junction_names, const LoopClosureRecord& loop_closure,
    double max_gap_share) {
  std::vector<std::string> reasons;
  for (std::size_t i = 0; i < t_intersections.size(); ++i) {
    const TIntersectionRecord& t = t_intersections[i];
    if (t.rejection == "no turn" || InsideHeldLoop(t.section, loop_closure, max_gap_share)) {
      continue;
    }
    const std::string name = i < junction_names.size() && !junction_names[i].empty()
                                 ? "junction " + junction_names[i]
                                 : "the T-intersection";
    const std::string where =
        fmt::format("{} (key frames {}-{})", name, t.red_keyframe, t.blue_keyframe);
    if (t.phi_given) {
      const double held = t.model[kPhi] * 180.0 / M_PI;
      const double own = t.initial_model[kPhi] * 180.0 / M_PI;
      const std::string check =
          std::abs(own - held) <= kMaxFittingAngleDisagreementDeg
              ? fmt::format("its end cylinders meet at {:.1f} deg", own)
              : fmt::format(
                    "but its end cylinders meet at {:.1f} deg, more than {:.0f} deg from it: the "
                    "fitting may not be what was given",
                    own, kMaxFittingAngleDisagreementDeg);
      reasons.push_back(fmt::format(
          "the turn at {} was held at the given fitting angle ({:.1f} deg, t_fitting_angle_deg; "
          "{}) and no closed loop confirms it, nor the heading of the pipes on either side: "
          "positions past it are not confirmed",
          where, held, check));
      continue;
    }
    const std::string measured =
        t.rejection.empty()
            ? fmt::format("rests on the T model alone (phi {:.1f} deg, measured)",
                          t.model[kPhi] * 180.0 / M_PI)
            : "rests on the chained key frames alone (the T model was not applied: " + t.rejection +
                  ")";
    reasons.push_back("the turn at " + where + " " + measured +
                      " and no closed loop confirms it, nor the heading of the pipes on either "
                      "side: positions past it are not confirmed");
  }
  return reasons;
}

}  // namespace pipescope
