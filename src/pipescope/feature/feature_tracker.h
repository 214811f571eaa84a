#pragma once

#include <Eigen/Core>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "pipescope/camera/camera.h"
#include "pipescope/feature/guided_zncc.h"
#include "pipescope/feature/region_harris.h"
#include "pipescope/feature/template_descriptor.h"
#include "pipescope/geometry/sphere_relative_pose.h"

namespace pipescope {

// Feature tracking with key framing (001 §III-A): region Harris, template descriptors matched by
// cosine similarity against the last key frame, relative pose with RANSAC on the sphere,
// epipolar-guided ZNCC for the key frame's unmatched features, and a new key frame when the
// median flow is large enough or the share of corresponding features drops. Features are
// tracked over many frames by matching key frame to key frame recursively: a matched feature
// keeps its track id.
// 001's region Harris: 2 x 2 regions, the strongest 200 of each (after Nister et al. [6]), a 7 x 7
// box window (larger than 3 against sensor noise), integer positions, 16 px clear of the border
// so the 31 x 31 descriptor region fits.
RegionHarrisOptions FisheyeRegionHarrisOptions();

// How the frames after a key frame find its features (FeatureTrackerOptions::matcher).
// 001 §III-A: region Harris corners detected in every frame, their template descriptors matched
// by cosine similarity against the key frame's.
inline constexpr const char* kTemplateMatcher = "templates";
// The key frame's features followed frame to frame by pyramidal Lucas-Kanade, each step checked
// by tracking back; corners are detected only at key frames. A template match needs the same
// corner to win in both images; Lucas-Kanade integrates a 21 x 21 window, so weak texture under
// noise keeps its tracks (docs/conditions.md).
inline constexpr const char* kLucasKanadeMatcher = "lucas-kanade";

struct FeatureTrackerOptions {
  // Lucas-Kanade since the fifteenth session: on the 8.4 m straight benchmark -0.026 % against
  // -0.076 %, on the 1100-frame network 0.010 % against 0.943 % with its Ts at 90.8 and 90.1
  // degrees (templates: 92.7, 91.4), and it holds under noise σ 2-3 where templates lose the
  // run (docs/fisheye_mapping.md, "Following the features").
  std::string matcher = kLucasKanadeMatcher;
  // Lucas-Kanade: window, pyramid levels, and the round trip a track must return within.
  int lk_window_px = 21;
  int lk_pyramid_levels = 3;
  double lk_max_round_trip_px = 0.5;
  // Lucas-Kanade follows the frames flat-fielded with this sigma (image/flat_field.h): the
  // lights ride with the camera, and on the rendered preset the shading held the tracks to
  // about half the true flow.
  double lk_flat_field_sigma_px = 8.0;
  // Lucas-Kanade: corners a region holds at a key frame, followed ones first (the templates take
  // harris.per_cell, 001's 200). Followed tracks live long: at 200 the window adjustments have
  // twice the templates' observations. With windows every 10 key frames the 8.4 m benchmark took
  // 146-159 s against the templates' 87-95 s, and 100 a region 87 s at some accuracy (ATE 3.4
  // against 3.3 mm; the 1100-frame network 0.473 % against 0.010 %); with windows every 20 (the
  // default since) 200 takes 96-106 s. Every figure under noise and on the routes was measured
  // at 200 (docs/fisheye_mapping.md).
  int lk_features_per_region = 200;
  RegionHarrisOptions harris = FisheyeRegionHarrisOptions();
  TemplateDescriptorOptions descriptor;
  CosineMatchOptions matching;
  SphereRelativePoseOptions relative_pose;
  GuidedZnccOptions guided;
  bool guided_matching = true;
  // No features farther than this from the optical axis. The lens sees to 95 degrees (001:
  // 190), but past about 80 degrees the wall lies within 3.5 cm of the lens in a 400 mm pipe, a
  // 1 cm key-frame step changes its view by tens of pixels. On the 8.4 m straight benchmark:
  // 95 degrees -1.34 % with 6 frames RANSAC could not match and a tracking reset, 80 degrees
  // -0.40 %, 70 degrees -0.06 %, no failures (docs/fisheye_mapping.md, "View angle").
  double max_view_angle_deg = 70.0;
  // Besides each quarter's strongest corners, up to this many of the strongest within
  // far_wall_cone_deg of the optical axis (feature/far_wall_corners.h). 0: none, the default
  // until measured further: 150 within 35 degrees took the turns through six simulated Ts from
  // 1.3-11.8 degrees off to 2.3-4.6, at 9 % more time on the straight benchmark
  // (docs/fisheye_mapping.md, "Turns confirmed or not").
  int far_wall_corners = 0;
  double far_wall_cone_deg = 35.0;
  // Key frame when the median flow to the last key frame reaches this, or when the next frame's
  // would pass max_median_flow_px at the recent pace (flow per frame, this span's and the last
  // three spans', their upper median). So a crawler at 1 cm a frame, 001's benchmark here with
  // 8.5-12 px a frame, keeps every frame as a key frame, also where one frame's flow drops to
  // 6 px inside a T (this span's pace alone dropped one there, and the T then ended 15 % short);
  // at 1.3 mm a frame the key frames are 7-10 frames apart, at 10-12 px ...
  double min_median_flow_px = 10.0;
  double max_median_flow_px = 15.0;
  // ... or the RANSAC inliers fall below this fraction of those of the first frame tracked after
  // the key frame (001: "both minimums are selected empirically"). Measured against the key
  // frame's features instead, as before, the share was under 0.4 at every frame (about 800
  // features, up to 800 of them fresh detections matched once at most): every frame became a
  // key frame, and a crawler at 1.3 mm a frame (001's 9.5 mm/s at 7.5 fps) gave key frames
  // too close for their parallax (docs/fisheye_mapping.md, "A slow crawler").
  double min_correspondence_fraction = 0.4;
  // Fewer RANSAC inliers than this: the frame cannot be used.
  int min_inliers = 30;
  // A new detection this close to a tracked feature is the same feature.
  double duplicate_radius_px = 3.0;
};

struct TrackedFeature {
  long track_id = -1;
  cv::Point2f pixel;
  Eigen::Vector3d bearing;
};

// A key frame's features and its link to the previous key frame.
struct TrackedKeyframe {
  int frame_index = 0;
  std::vector<TrackedFeature> features;
  // From the previous key frame: cam_this_from_cam_previous up to scale, and match counts.
  bool has_previous = false;
  SphereRelativePose relative_pose;
  // The previous key frame's features carried over: template matches (or followed features,
  // with kLucasKanadeMatcher), then those found by guided ZNCC (templates only).
  int matches_cosine = 0;
  int matches_guided = 0;
  double median_flow_px = 0.0;
};

struct TrackingStep {
  bool keyframe = false;
  bool usable = true;   // false: the frame could not be matched to the key frame
  std::string failure;  // why not usable
  double median_flow_px = 0.0;
  double correspondence_fraction = 0.0;
  int inliers = 0;
};

class FeatureTracker {
 public:
  FeatureTracker(const Camera& camera, const FeatureTrackerOptions& options = {});

  // Tracks `grey` (CV_32F, the camera's size) against the last key frame. The first frame is
  // always a key frame. When the step makes a key frame, `*keyframe` receives it.
  TrackingStep Track(const cv::Mat& grey, int frame_index, TrackedKeyframe* keyframe);

  // Starts over: the next frame becomes a key frame without a link to the previous one (the
  // last step stays the motion prior).
  void Reset() {
    last_.reset();
    follow_pyramid_frame_ = -1;
  }

  const BearingTable& bearings() const { return bearings_; }
  // The last key frame's template descriptors, one row per feature of its TrackedKeyframe (none
  // with kLucasKanadeMatcher).
  const cv::Mat& keyframe_descriptors() const { return last_ ? last_->descriptors : empty_; }

 private:
  struct KeyframeState {
    int frame_index;
    cv::Mat grey;
    std::vector<TrackedFeature> features;
    std::vector<cv::Point2f> points;
    cv::Mat descriptors;
  };

  std::vector<cv::Point2f> Detect(const cv::Mat& grey) const;
  // Follows the key frame's features into `grey` (kLucasKanadeMatcher): the matches
  // of last_->features (index_a) to `*points` (index_b), the pixels they were followed to.
  std::vector<FeatureMatch> FollowFeatures(const cv::Mat& grey, int frame_index,
                                           std::vector<cv::Point2f>* points);
  // What Lucas-Kanade follows: `grey` flat-fielded (lk_flat_field_sigma_px), CV_8U.
  cv::Mat FollowedImage(const cv::Mat& grey) const;
  // Starts following `grey`'s key-frame features (last_) anew.
  void StartFollowing(const cv::Mat& grey, int frame_index);
  bool Bearing(const cv::Point2f& pixel, Eigen::Vector3d* bearing) const;
  // Whether a frame `frames_since_keyframe` after the key frame, with this median flow to it,
  // ends the span by its flow: it reached min_median_flow_px, or the next frame's would pass
  // max_median_flow_px.
  bool FlowEndsSpan(double median_flow_px, int frames_since_keyframe) const;
  // `detection_rows[k]`: the row of `detection_descriptors` already computed at features[k]'s
  // pixel in this image, or -1 (then it is computed here); empty: all are computed here.
  void MakeKeyframe(const cv::Mat& grey, int frame_index, std::vector<TrackedFeature> features,
                    TrackedKeyframe* keyframe, const cv::Mat& detection_descriptors = cv::Mat(),
                    const std::vector<int>& detection_rows = {});

  const Camera& camera_;
  FeatureTrackerOptions options_;
  BearingTable bearings_;
  cv::Mat detection_mask_;
  cv::Mat far_wall_mask_;  // detection_mask_ within far_wall_cone_deg of the optical axis
  std::unique_ptr<KeyframeState> last_;
  // Lucas-Kanade: the previous frame's pyramid, and where each followed feature of last_ is
  // (its index in last_->features, its pixel in the previous frame).
  std::vector<cv::Mat> follow_pyramid_;
  int follow_pyramid_frame_ = -1;  // the frame follow_pyramid_ was built from
  std::vector<int> follow_feature_;
  std::vector<cv::Point2f> follow_points_;
  std::optional<SphereRelativePose> last_motion_;  // the last key-frame step, a RANSAC prior
  int span_start_inliers_ = 0;  // of the first frame tracked after the last key frame; 0: none yet
  // The flow per frame of each of the last kRecentSpans key-frame spans (the crawler's pace).
  static constexpr std::size_t kRecentSpans = 3;
  std::vector<double> recent_flow_per_frame_;
  long next_track_id_ = 0;
  cv::Mat empty_;
};

}  // namespace pipescope
