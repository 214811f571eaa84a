#include "pipescope/image/settled_sections.h"

#include <algorithm>

namespace pipescope {

std::vector<KeyframeSection> SettledSections::Add(PipeViewClass initial) {
  initial_.push_back(initial);
  const int settled = SettledPipeViewClassCount(initial_, min_cluster_size_);
  // A key frame needs its successor settled too: that tells whether it ends its section.
  if (settled - 1 <= released_) return {};
  const std::vector<PipeViewClass> prefix(initial_.begin(), initial_.begin() + settled);
  return Release(FilterPipeViewClasses(prefix, min_cluster_size_), settled - 1);
}

std::vector<KeyframeSection> SettledSections::Finish() {
  return Release(FilterPipeViewClasses(initial_, min_cluster_size_),
                 static_cast<int>(initial_.size()));
}

std::vector<KeyframeSection> SettledSections::Release(const std::vector<PipeViewClass>& filtered,
                                                      int end) {
  std::vector<KeyframeSection> released;
  for (int k = released_; k < end; ++k) {
    if (k == 0 || filtered[k] != filtered[k - 1]) {
      ++section_;
      section_first_keyframe_ = k;
    }
    const bool last = k + 1 == static_cast<int>(filtered.size()) || filtered[k + 1] != filtered[k];
    released.push_back({k, section_, filtered[k], section_first_keyframe_, last});
  }
  released_ = std::max(released_, end);
  return released;
}

}  // namespace pipescope
