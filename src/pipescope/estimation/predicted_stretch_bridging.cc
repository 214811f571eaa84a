#include "pipescope/estimation/predicted_stretch_bridging.h"

#include <stdexcept>

namespace pipescope {

std::vector<std::size_t> BridgePredictedStretches(const std::vector<FrameMeasurement>& frames,
                                                  Trajectory* trajectory) {
  if (frames.size() != trajectory->size()) {
    throw std::invalid_argument("BridgePredictedStretches: one measurement per pose");
  }
  std::vector<std::size_t> bridged;
  std::size_t i = 0;
  while (i < frames.size()) {
    if (!frames[i].predicted) {
      ++i;
      continue;
    }
    std::size_t end = i;  // one past the stretch
    bool carried_by_key = false;
    while (end < frames.size() && frames[end].predicted) carried_by_key |= frames[end++].became_key;
    if (i > 0 && end < frames.size() && !carried_by_key) {
      const StampedPose& before = (*trajectory)[i - 1];
      const StampedPose& after = (*trajectory)[end];
      const double span = after.timestamp - before.timestamp;
      for (std::size_t k = i; k < end; ++k) {
        const double t = span > 0.0 ? ((*trajectory)[k].timestamp - before.timestamp) / span : 0.5;
        (*trajectory)[k].position = (1.0 - t) * before.position + t * after.position;
        (*trajectory)[k].rotation = before.rotation.slerp(t, after.rotation);
        bridged.push_back(k);
      }
    }
    i = end;
  }
  return bridged;
}

}  // namespace pipescope
