#include "pipescope/pipeline/window_confirmation.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

namespace pipescope {

std::vector<std::string> WindowConfirmationReasons(const std::vector<OdometryWindowRecord>& windows,
                                                   int longest_straight_section,
                                                   const WindowConfirmationOptions& options) {
  int straight = 0;
  int rejected = 0;
  std::map<std::string, int> why;
  for (const OdometryWindowRecord& window : windows) {
    if (!window.straight) continue;  // T-intersection windows do not set the scale
    ++straight;
    if (window.rejection.empty()) continue;
    ++rejected;
    ++why[window.rejection];
  }
  std::vector<std::string> reasons;
  if (straight == 0) {
    if (longest_straight_section >= options.window_interval) {
      reasons.push_back("no window adjustment ran in a straight section of " +
                        std::to_string(longest_straight_section) +
                        " key frames: the scale rests on single steps");
    }
    return reasons;
  }
  if (rejected > options.max_rejected_share * straight) {
    std::ostringstream reason;
    reason << rejected << " of " << straight << " window adjustments were rejected (";
    const char* separator = "";
    for (const auto& [rejection, count] : why) {
      reason << separator << rejection << ": " << count;
      separator = ", ";
    }
    reason << "; limit " << std::lround(100 * options.max_rejected_share)
           << " %): the scale rests on single steps";
    reasons.push_back(reason.str());
  }
  return reasons;
}

std::vector<std::string> WindowConfirmationReasons(const FisheyeMappingResult& result,
                                                   const FisheyeMappingOptions& options) {
  int longest_straight_section = 0;
  for (const FisheyeSection& section : result.sections) {
    if (section.view_class != PipeViewClass::kStraight) continue;
    longest_straight_section =
        std::max(longest_straight_section, section.last_keyframe - section.first_keyframe + 1);
  }
  WindowConfirmationOptions confirmation;
  confirmation.max_rejected_share = options.max_rejected_window_share;
  confirmation.window_interval = options.odometry.window_interval;
  return WindowConfirmationReasons(result.windows, longest_straight_section, confirmation);
}

}  // namespace pipescope
