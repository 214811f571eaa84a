#include "pipescope/report/run_quality.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "pipescope/util/median.h"

namespace pipescope {
namespace {

std::string Percent(double share) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.1f %%", 100.0 * share);
  return buffer;
}

}  // namespace

RunQuality AssessRunQuality(const std::vector<FrameState>& states, const RunQualityLimits& limits) {
  RunQuality quality;
  quality.frames = static_cast<int>(states.size());
  int stretch = 0, stretch_first = -1;
  for (int i = 0; i < quality.frames; ++i) {
    switch (states[i]) {
      case FrameState::kMeasured:
        ++quality.measured;
        stretch = 0;
        break;
      case FrameState::kPredicted:
        ++quality.predicted;
        quality.predicted_frames.push_back(i);
        if (stretch++ == 0) stretch_first = i;
        if (stretch > quality.longest_predicted_stretch) {
          quality.longest_predicted_stretch = stretch;
          quality.longest_stretch_first_frame = stretch_first;
        }
        break;
      case FrameState::kBridged:
        // Bounded by measurements on both sides: not a guess carried forward.
        ++quality.bridged;
        quality.bridged_frames.push_back(i);
        stretch = 0;
        break;
      case FrameState::kNotLocalised:
        ++quality.not_localised;
        quality.not_localised_frames.push_back(i);
        break;
    }
  }
  const double frames = std::max(1, quality.frames);
  if (quality.measured < 2) {
    quality.reasons.push_back("fewer than 2 frames were measured");
  }
  if (quality.predicted / frames > limits.max_predicted_share) {
    quality.reasons.push_back(Percent(quality.predicted / frames) +
                              " of the frames were predicted, not measured (limit " +
                              Percent(limits.max_predicted_share) + ")");
  }
  if (quality.longest_predicted_stretch > limits.max_predicted_stretch) {
    quality.reasons.push_back(std::to_string(quality.longest_predicted_stretch) +
                              " frames in a row were predicted from frame " +
                              std::to_string(quality.longest_stretch_first_frame) + " (limit " +
                              std::to_string(limits.max_predicted_stretch) + ")");
  }
  if (quality.not_localised / frames > limits.max_not_localised_share) {
    quality.reasons.push_back(Percent(quality.not_localised / frames) +
                              " of the frames have no pose (limit " +
                              Percent(limits.max_not_localised_share) + ")");
  }
  quality.reliable = quality.reasons.empty();
  return quality;
}

RunQualityLimits KeyframeQualityLimits(const std::vector<int>& keyframe_frames,
                                       const RunQualityLimits& base) {
  std::vector<double> spacing;
  for (std::size_t k = 1; k < keyframe_frames.size(); ++k) {
    spacing.push_back(keyframe_frames[k] - keyframe_frames[k - 1]);
  }
  RunQualityLimits limits = base;
  limits.max_predicted_stretch *= std::max(1, static_cast<int>(std::lround(Median(spacing))));
  return limits;
}

nlohmann::json RunQualityJson(const RunQuality& quality, const RunQualityLimits& limits) {
  const double frames = std::max(1, quality.frames);
  return {{"verdict", quality.reliable ? "reliable" : "unreliable"},
          {"reasons", quality.reasons},
          {"along_pipe_verdict", quality.AlongPipeReliable() ? "reliable" : "unreliable"},
          {"position_reasons", quality.position_reasons},
          {"frames", quality.frames},
          {"frames_measured", quality.measured},
          {"frames_predicted", quality.predicted},
          {"frames_bridged", quality.bridged},
          {"frames_not_localised", quality.not_localised},
          {"predicted_share", quality.predicted / frames},
          {"not_localised_share", quality.not_localised / frames},
          {"longest_predicted_stretch", quality.longest_predicted_stretch},
          {"longest_predicted_stretch_first", quality.longest_stretch_first_frame},
          {"predicted_frames", quality.predicted_frames},
          {"bridged_frames", quality.bridged_frames},
          {"not_localised_frames", quality.not_localised_frames},
          {"limits",
           {{"max_predicted_share", limits.max_predicted_share},
            {"max_predicted_stretch", limits.max_predicted_stretch},
            {"max_not_localised_share", limits.max_not_localised_share}}}};
}

std::string RunQualitySummary(const RunQuality& quality) {
  const std::string counts = "(" + std::to_string(quality.measured) + " of " +
                             std::to_string(quality.frames) + " frames measured, " +
                             std::to_string(quality.bridged) + " bridged, " +
                             std::to_string(quality.predicted) + " predicted, " +
                             std::to_string(quality.not_localised) + " without a pose)";
  if (quality.reliable) return "quality: reliable " + counts;
  std::string reasons;
  for (const std::string& reason : quality.reasons) {
    reasons += (reasons.empty() ? "" : "; ") + reason;
  }
  if (quality.AlongPipeReliable()) {
    return "quality: UNRELIABLE positions: " + reasons +
           "; distances along the pipe are reliable " + counts;
  }
  return "quality: UNRELIABLE: " + reasons + "; do not trust this run's distances";
}

std::vector<std::string> AlongPipeReasons(const nlohmann::json& quality_json) {
  const nlohmann::json no_positions = nlohmann::json::array();
  const nlohmann::json& positions =
      quality_json.contains("position_reasons") ? quality_json["position_reasons"] : no_positions;
  std::vector<std::string> reasons;
  for (const nlohmann::json& reason : quality_json["reasons"]) {
    if (std::find(positions.begin(), positions.end(), reason) == positions.end()) {
      reasons.push_back(reason.get<std::string>());
    }
  }
  return reasons;
}

}  // namespace pipescope
