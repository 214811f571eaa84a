#pragma once

#include <string>
#include <vector>

#include "pipescope/pipeline/sparse_vo.h"

namespace pipescope {

// What a sparse run found wrong with its own result beyond its frames' states: each reason makes
// the run unreliable (run.json `quality`, docs/formats.md). Three checks:
// - its key frames stray more than `max_cross_section_excursion` of the radius across the pipe
//   from the first (the images did not hold the camera's distance to the wall);
// - where the view cannot measure the wall distance, they stray more than
//   `max_unobserved_excursion` of that distance (the scale follows an unconfirmed excursion);
// - the key frames' median of tracked keypoints is below `min_median_tracked`: too little
//   structure to measure the wall distance (on faint, noisy wall 12-26, against 200-570 where
//   the runs held; a run at 26 ended 1.9 % off; docs/conditions.md).
std::vector<std::string> SparseVoVerdictReasons(const SparseVoResult& result,
                                                const SparseVoOptions& options, double radius_m);

}  // namespace pipescope
