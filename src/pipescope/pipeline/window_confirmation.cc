#include "pipescope/pipeline/window_confirmation.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <string>
#include <utility>

namespace pipescope {

namespace {

// "image rms: 2, path length: 1": why the windows were rejected, by count.
std::string RejectionCounts(const std::map<std::string, int>& why) {
  std::ostringstream counts;
  const char* separator = "";
  for (const auto& [rejection, count] : why) {
    counts << separator << rejection << ": " << count;
    separator = ", ";
  }
  return counts.str();
}

// One reason per straight section whose own windows were mostly rejected.
std::vector<std::string> SectionReasons(const std::vector<OdometryWindowRecord>& windows,
                                        const WindowConfirmationOptions& options) {
  const std::map<int, StraightSectionWindows> sections = CountStraightSectionWindows(windows);
  std::vector<std::string> reasons;
  for (const auto& [index, section] : sections) {
    if (section.windows < options.min_section_windows) continue;
    if (section.rejected <= options.max_rejected_section_share * section.windows) continue;
    std::ostringstream reason;
    reason << "straight section " << index << " (key frames " << section.first_keyframe << "-"
           << section.last_keyframe << "): " << section.rejected << " of " << section.windows
           << " window adjustments were rejected (" << RejectionCounts(section.why) << "; limit "
           << std::lround(100 * options.max_rejected_section_share)
           << " % a section): its length rests on single steps";
    reasons.push_back(reason.str());
  }
  return reasons;
}

}  // namespace

std::map<int, StraightSectionWindows> CountStraightSectionWindows(
    const std::vector<OdometryWindowRecord>& windows) {
  std::map<int, StraightSectionWindows> sections;
  for (const OdometryWindowRecord& window : windows) {
    if (!window.straight) continue;
    auto [it, added] = sections.try_emplace(window.section);
    StraightSectionWindows& section = it->second;
    if (added) section.first_keyframe = window.first_keyframe;
    section.first_keyframe = std::min(section.first_keyframe, window.first_keyframe);
    section.last_keyframe = std::max(section.last_keyframe, window.last_keyframe);
    ++section.windows;
    if (window.rejection.empty()) continue;
    ++section.rejected;
    ++section.why[window.rejection];
  }
  return sections;
}

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
    if (longest_straight_section >= options.min_window_keyframes) {
      reasons.push_back("no window adjustment ran in a straight section of " +
                        std::to_string(longest_straight_section) +
                        " key frames: the scale rests on single steps");
    }
    return reasons;
  }
  if (rejected > options.max_rejected_share * straight) {
    std::ostringstream reason;
    reason << rejected << " of " << straight << " window adjustments were rejected ("
           << RejectionCounts(why) << "; limit " << std::lround(100 * options.max_rejected_share)
           << " %): the scale rests on single steps";
    reasons.push_back(reason.str());
  }
  for (std::string& reason : SectionReasons(windows, options)) reasons.push_back(std::move(reason));
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
  confirmation.max_rejected_section_share = options.max_rejected_section_window_share;
  confirmation.min_window_keyframes = options.odometry.min_window_keyframes;
  return WindowConfirmationReasons(result.windows, longest_straight_section, confirmation);
}

}  // namespace pipescope
