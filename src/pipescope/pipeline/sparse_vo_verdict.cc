#include "pipescope/pipeline/sparse_vo_verdict.h"

#include <fmt/format.h>

#include "pipescope/pipeline/wall_distance_statement.h"
#include "pipescope/util/median.h"

namespace pipescope {

std::vector<std::string> SparseVoVerdictReasons(const SparseVoResult& result,
                                                const SparseVoOptions& options, double radius_m) {
  std::vector<std::string> reasons;
  if (options.max_cross_section_excursion > 0.0 &&
      result.cross_section_excursion_m > options.max_cross_section_excursion * radius_m) {
    reasons.push_back(fmt::format(
        "the estimated camera strays {:.1f} mm across the pipe from its start (limit {:.0f} % of "
        "the radius, {:.1f} mm): the images did not hold its distance to the wall, so the scale "
        "is not to be trusted",
        1000.0 * result.cross_section_excursion_m, 100.0 * options.max_cross_section_excursion,
        1000.0 * options.max_cross_section_excursion * radius_m));
  }
  const std::string unobserved = UnobservedExcursionReason(
      result.wall_distance, result.cross_section_excursion_m, options.max_unobserved_excursion);
  if (!unobserved.empty()) reasons.push_back(unobserved);
  // The first key frame has nothing to track: the median is over the others.
  const std::vector<SparseKeyFrameRecord>& key_frames = result.summary.key_frame_records;
  std::vector<double> tracked_counts;
  for (std::size_t k = 1; k < key_frames.size(); ++k)
    tracked_counts.push_back(key_frames[k].tracked);
  const double tracked = UpperMedian(tracked_counts);
  if (options.min_median_tracked > 0 && !tracked_counts.empty() &&
      tracked < options.min_median_tracked) {
    reasons.push_back(fmt::format(
        "its key frames track a median of {:.0f} keypoints (limit {}): too little of the wall is "
        "matched to measure the camera's distance to it, so the scale is not to be trusted",
        tracked, options.min_median_tracked));
  }
  return reasons;
}

}  // namespace pipescope
