#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace pipescope {

// What a run knows of each frame's pose (issue 22: no silent failure).
enum class FrameState {
  kMeasured,      // registered: the pose comes from this frame's own measurement
  kPredicted,     // the measurement failed; the pose continues the recent motion
  kBridged,       // the measurement failed; the pose is interpolated between measured ones
  kNotLocalised,  // no pose: unreadable, skipped or not matched
};

// When a run stops being reliable. A prediction at constant velocity is a guess: a few frames
// of it cost little, a stretch of them or a share of them makes the distance a guess too.
struct RunQualityLimits {
  double max_predicted_share = 0.05;
  int max_predicted_stretch = 5;  // frames in a row
  double max_not_localised_share = 0.05;
};

struct RunQuality {
  int frames = 0;
  int measured = 0;
  int predicted = 0;
  int bridged = 0;
  int not_localised = 0;
  int longest_predicted_stretch = 0;
  int longest_stretch_first_frame = -1;  // index into the states, -1 without a stretch
  std::vector<int> predicted_frames;
  std::vector<int> bridged_frames;
  std::vector<int> not_localised_frames;
  bool reliable = true;
  std::vector<std::string> reasons;  // why it is unreliable; empty when reliable
  // Of `reasons`, those that leave the distances along the pipe standing: what makes only the
  // positions across the pipe's turns unconfirmed (a map run's T-intersections, an ekf run's
  // bends).
  std::vector<std::string> position_reasons;
  // Whether the distances along the pipe (stations, sections) are reliable: no reason but
  // position reasons.
  bool AlongPipeReliable() const { return reasons.size() == position_reasons.size(); }
};

// Counts the states (in frame order) and gives the verdict, with a reason per limit exceeded.
// Not-localised frames between predicted ones do not break a stretch: the pose after them still
// rests on the prediction.
RunQuality AssessRunQuality(const std::vector<FrameState>& states,
                            const RunQualityLimits& limits = {});

// For a method whose frames between key frames are interpolated (`map`): a key frame whose
// relative pose was rejected makes every frame since the key frame before it predicted, and a
// slow crawler has several frames between key frames (about 8 at 001's 1.3 mm a frame). The
// stretch limit then counts key-frame steps: `base`'s stretch times the median spacing of
// `keyframe_frames` (the key frames' frame indices, increasing), at least 1.
RunQualityLimits KeyframeQualityLimits(const std::vector<int>& keyframe_frames,
                                       const RunQualityLimits& base = {});

// run.json's `quality` block: counts, shares, the longest stretch, the frame lists, `verdict`
// ("reliable" or "unreliable") and `reasons`.
nlohmann::json RunQualityJson(const RunQuality& quality, const RunQualityLimits& limits = {});

// The line the user sees: "quality: reliable (...)", "quality: UNRELIABLE: reasons" or, when only
// positions are in doubt, "quality: UNRELIABLE positions: reasons; distances along the pipe
// reliable (...)".
std::string RunQualitySummary(const RunQuality& quality);

// Of a `quality` block as RunQualityJson writes it, the reasons against the distances along the
// pipe (`reasons` less `position_reasons`), in order; empty when they hold. A block written
// before `position_reasons` existed counts every reason.
std::vector<std::string> AlongPipeReasons(const nlohmann::json& quality_json);

}  // namespace pipescope
