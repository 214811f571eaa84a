#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <unordered_map>
#include <utility>
#include <vector>

#include "pipescope/camera/camera.h"
#include "pipescope/estimation/initial_position.h"

namespace pipescope {

// Joint adjustment of a window of key-frame poses (beyond 000, which refines one pose at a time,
// §5.3.3): all six degrees of freedom of every free key frame minimise the reprojection error of
// every track through the cylinder (CylinderTransferCost), so rotation and translation are
// separated by all the views together instead of frame by frame (000 §5.3.4, Fig. 10).
struct WindowAdjustmentOptions {
  double robust_loss_px = 1.0;  // Cauchy scale on the reprojection error
  int max_iterations = 15;
  // Weight (1/metres and 1/radians) of the gauge prior when no key frame is held fixed.
  double gauge_weight = 1e4;
  // When no key frame is fixed: also hold the first key frame's position across the pipe (C_X,
  // C_Y), i.e. its measured distance to the wall (000 §3.3, §5.3.2: "measured manually"). The
  // reprojections through the cylinder see that distance only through the wall's curvature,
  // which a narrow lens barely sees; left free, it (and with it the scale) follows the
  // keypoints' localisation bias.
  bool hold_first_cross_section = false;
  // Sigma (metres) of CrossSectionSmoothnessCost between consecutive key frames; 0: none.
  double cross_section_step_sigma_m = 0.0;
  // Sigma (metres) of CrossSectionAnchorCost on every free key frame, pulling its C_X, C_Y
  // towards cross_section_anchor_xy (the measured start); 0: none.
  double cross_section_anchor_sigma_m = 0.0;
  Eigen::Vector2d cross_section_anchor_xy = Eigen::Vector2d::Zero();
  // A Cauchy loss of scale 1 on the anchor's residual: within sigma it holds like the Gaussian
  // prior, beyond it its pull fades (as 1/offset), so reprojections that see the wall's curvature
  // overrule it while views that cannot see it keep the start's level.
  bool cross_section_anchor_robust = false;
};

struct WindowKeyFrame {
  Eigen::Isometry3d pose;  // world_from_cam; updated in place
  bool fixed = false;
  std::vector<KeyFrameKeypoint> keypoints;
};

// Calls visit(a, reference, b, seen) for every later sighting `seen` (in key frame b) of a track
// whose first sighting in these key frames is `reference` (in key frame a < b), in key-frame
// order: the pairs every cylinder-transfer residual is built from.
template <typename Visit>
void ForEachLaterSighting(const std::vector<WindowKeyFrame>& key_frames, Visit visit) {
  std::unordered_map<long long, std::pair<std::size_t, std::size_t>> first;
  for (std::size_t b = 0; b < key_frames.size(); ++b) {
    for (std::size_t j = 0; j < key_frames[b].keypoints.size(); ++j) {
      const KeyFrameKeypoint& seen = key_frames[b].keypoints[j];
      const auto [it, inserted] = first.emplace(seen.track, std::make_pair(b, j));
      if (inserted) continue;
      const auto [a, i] = it->second;
      visit(a, key_frames[a].keypoints[i], b, seen);
    }
  }
}

struct WindowAdjustmentSummary {
  int residuals = 0;
  double initial_rms_px = 0.0;
  double final_rms_px = 0.0;
};

// Each track seen in two or more of the window's key frames gives one residual from its first
// sighting a to every later sighting b. When no key frame is fixed, the first one's travel and
// roll about the axis are held by CylinderGaugeCost.
WindowAdjustmentSummary AdjustWindow(const Camera& camera, double radius_m,
                                     const WindowAdjustmentOptions& options,
                                     std::vector<WindowKeyFrame>* key_frames);

}  // namespace pipescope
