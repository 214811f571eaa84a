#pragma once

#include <vector>

#include "pipescope/image/pipe_view_classification.h"

namespace pipescope {

// A key frame's place among the filtered sections (runs of one filtered class).
struct KeyframeSection {
  int keyframe = 0;
  int section = 0;  // index of the section, counted from the first key frame
  PipeViewClass view_class = PipeViewClass::kStraight;
  int first_keyframe = 0;        // of the section
  bool last_in_section = false;  // the section's last key frame
};

// Sections of the key frames as their initial classes arrive one by one: a key frame is given
// out once its filtered class and whether it ends its section (its successor's class) can no
// longer change (SettledPipeViewClassCount), so that the odometry can run behind the tracking
// yet see exactly the sections of the whole sequence's temporal filter (001 §III-B).
class SettledSections {
 public:
  explicit SettledSections(int min_cluster_size) : min_cluster_size_(min_cluster_size) {}

  // The next key frame's initial class; returns the key frames settled by it, in order.
  std::vector<KeyframeSection> Add(PipeViewClass initial);

  // The sequence has ended: returns the remaining key frames, the last one ending its section.
  std::vector<KeyframeSection> Finish();

 private:
  // Gives out key frames up to (not including) `end` from the filtered classes.
  std::vector<KeyframeSection> Release(const std::vector<PipeViewClass>& filtered, int end);

  int min_cluster_size_;
  std::vector<PipeViewClass> initial_;
  int released_ = 0;  // key frames given out so far
  int section_ = -1;  // the last given-out key frame's section
  int section_first_keyframe_ = 0;
};

}  // namespace pipescope
