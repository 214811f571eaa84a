#pragma once

#include <map>
#include <string>
#include <vector>

#include "pipescope/estimation/keyframe_odometry.h"
#include "pipescope/pipeline/fisheye_mapping.h"

namespace pipescope {

// Whether the window bundle adjustments confirmed a fisheye map's scale. Each key-frame step is
// scaled by fitting the pipe's radius to the points it sees; the windows (001 §III-C) adjust
// the steps jointly and correct the bias of the single steps (on a clean 2 m straight run the
// first window shortens the chained path by 18 %). A window that does not converge is rejected
// (keyframe_odometry.h), and where most of a straight pipe's windows are rejected its scale
// rests on the single steps alone: on faint noisy texture such runs ended 0.4-13 % off. One
// straight section can fail the same way inside a run whose other sections hold: on the
// 2800-frame network route the last section had 11 of its 26 windows rejected and came out 32 %
// short, while no other straight section had more than 2 of 78 rejected.
struct WindowConfirmationOptions {
  // More than this share of the straight windows rejected: the scale is not confirmed.
  double max_rejected_share = 0.5;
  // ... or of one straight section's windows, for a section with at least
  // `min_section_windows` of them (a few windows are too few to judge a share by).
  double max_rejected_section_share = 0.25;
  int min_section_windows = 4;
  // A straight section of this many key frames holds a window (the odometry's
  // min_window_keyframes: its last key frame runs one); a shorter one has none and needs none.
  int min_window_keyframes = 10;
};

// The straight windows of one section: how many, how many rejected and why, and the key frames
// they span.
struct StraightSectionWindows {
  int windows = 0;
  int rejected = 0;
  int first_keyframe = 0;
  int last_keyframe = 0;
  std::map<std::string, int> why;  // rejection -> count
};
std::map<int, StraightSectionWindows> CountStraightSectionWindows(
    const std::vector<OdometryWindowRecord>& windows);

// The reasons (empty: confirmed) for run.json's quality block. `longest_straight_section`: the
// key frames of the run's longest straight section.
std::vector<std::string> WindowConfirmationReasons(const std::vector<OdometryWindowRecord>& windows,
                                                   int longest_straight_section,
                                                   const WindowConfirmationOptions& options = {});

// The same for a map run: its windows and its longest straight section, with the limits of
// `options` (max_rejected_window_share, max_rejected_section_window_share, the odometry's
// min_window_keyframes).
std::vector<std::string> WindowConfirmationReasons(const FisheyeMappingResult& result,
                                                   const FisheyeMappingOptions& options);

}  // namespace pipescope
