#include "pipescope/feature/feature_tracker.h"

#include <algorithm>
#include <cmath>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "pipescope/feature/far_wall_corners.h"
#include "pipescope/feature/round_trip_flow.h"
#include "pipescope/image/flat_field.h"
#include "pipescope/util/median.h"

namespace pipescope {

RegionHarrisOptions FisheyeRegionHarrisOptions() {
  RegionHarrisOptions options;
  options.grid_rows = 2;
  options.grid_cols = 2;
  options.per_cell = 200;
  options.nms_window_px = 7;
  options.box_window_px = 7;
  options.sobel_aperture = 3;
  options.k = 0.04;
  options.border_px = 16;
  options.min_relative_response = 1e-6;
  options.subpixel = false;
  return options;
}

FeatureTracker::FeatureTracker(const Camera& camera, const FeatureTrackerOptions& options)
    : camera_(camera),
      options_(options),
      bearings_(camera, options.max_view_angle_deg * M_PI / 180.0) {
  // Corners only where their whole descriptor region lies inside the field of view.
  const int side = options_.descriptor.region_size_px;
  cv::erode(bearings_.valid_mask(), detection_mask_,
            cv::getStructuringElement(cv::MORPH_RECT, cv::Size(side, side)));
  if (options_.far_wall_corners > 0) {
    const BearingTable cone(camera, options_.far_wall_cone_deg * M_PI / 180.0);
    cv::bitwise_and(cone.valid_mask(), detection_mask_, far_wall_mask_);
  }
}

std::vector<cv::Point2f> FeatureTracker::Detect(const cv::Mat& grey) const {
  std::vector<cv::Point2f> points;
  RegionHarrisOptions harris = options_.harris;
  if (options_.matcher == kLucasKanadeMatcher) harris.per_cell = options_.lk_features_per_region;
  for (const Keypoint& keypoint : DetectRegionHarris(grey, harris, detection_mask_)) {
    points.push_back(keypoint.position);
  }
  if (options_.far_wall_corners > 0) {
    const std::vector<cv::Point2f> far =
        FarWallCorners(grey, far_wall_mask_, options_.harris, options_.far_wall_corners,
                       options_.duplicate_radius_px, points);
    points.insert(points.end(), far.begin(), far.end());
  }
  return points;
}

bool FeatureTracker::FlowEndsSpan(double median_flow_px, int frames_since_keyframe) const {
  if (median_flow_px >= options_.min_median_flow_px) return true;
  // At the same speed the next frame's flow grows by one frame's flow: this span's so far and
  // the last spans' per frame, their upper median, so that one frame of little flow (inside a T
  // at 1 cm a frame) does not drop a key frame where every frame is one.
  std::vector<double> flow_per_frame = recent_flow_per_frame_;
  flow_per_frame.push_back(median_flow_px / std::max(1, frames_since_keyframe));
  return median_flow_px + UpperMedian(flow_per_frame) > options_.max_median_flow_px;
}

bool FeatureTracker::Bearing(const cv::Point2f& pixel, Eigen::Vector3d* bearing) const {
  return camera_.Unproject(Eigen::Vector2d(pixel.x, pixel.y), bearing);
}

void FeatureTracker::MakeKeyframe(const cv::Mat& grey, int frame_index,
                                  std::vector<TrackedFeature> features, TrackedKeyframe* keyframe,
                                  const cv::Mat& detection_descriptors,
                                  const std::vector<int>& detection_rows) {
  auto state = std::make_unique<KeyframeState>();
  state->frame_index = frame_index;
  // Only the templates' guided search reads the key frame's image again.
  if (options_.matcher != kLucasKanadeMatcher) state->grey = grey.clone();
  state->features = std::move(features);
  for (const TrackedFeature& feature : state->features) state->points.push_back(feature.pixel);
  if (options_.matcher == kLucasKanadeMatcher) {
    // No descriptors: the features are followed, not matched.
  } else if (detection_rows.empty()) {
    state->descriptors = ComputeTemplateDescriptors(grey, state->points, options_.descriptor);
  } else {
    // A descriptor depends only on the image and the pixel: the detections' rows are copied,
    // only the guided matches' (sub-pixel, new places) are computed.
    std::vector<cv::Point2f> missing_points;
    for (std::size_t k = 0; k < state->points.size(); ++k) {
      if (detection_rows[k] < 0) missing_points.push_back(state->points[k]);
    }
    const cv::Mat missing = ComputeTemplateDescriptors(grey, missing_points, options_.descriptor);
    const int dim = options_.descriptor.descriptor_size * options_.descriptor.descriptor_size;
    state->descriptors.create(static_cast<int>(state->points.size()), dim, CV_32F);
    int next_missing = 0;
    for (std::size_t k = 0; k < state->points.size(); ++k) {
      const int row = static_cast<int>(k);
      if (detection_rows[k] >= 0) {
        detection_descriptors.row(detection_rows[k]).copyTo(state->descriptors.row(row));
      } else {
        missing.row(next_missing++).copyTo(state->descriptors.row(row));
      }
    }
  }
  keyframe->frame_index = frame_index;
  keyframe->features = state->features;
  last_ = std::move(state);
  span_start_inliers_ = 0;
  if (options_.matcher == kLucasKanadeMatcher) StartFollowing(grey, frame_index);
}

cv::Mat FeatureTracker::FollowedImage(const cv::Mat& grey) const {
  cv::Mat grey8;
  grey.convertTo(grey8, CV_8U);
  return FlatFieldedGrey8(grey8, options_.lk_flat_field_sigma_px);
}

void FeatureTracker::StartFollowing(const cv::Mat& grey, int frame_index) {
  // A key frame that was itself followed into has its pyramid built already.
  if (follow_pyramid_frame_ != frame_index) {
    const int window = options_.lk_window_px;
    follow_pyramid_.clear();
    cv::buildOpticalFlowPyramid(FollowedImage(grey), follow_pyramid_, cv::Size(window, window),
                                options_.lk_pyramid_levels);
    follow_pyramid_frame_ = frame_index;
  }
  follow_points_ = last_->points;
  follow_feature_.resize(follow_points_.size());
  for (std::size_t k = 0; k < follow_feature_.size(); ++k) follow_feature_[k] = static_cast<int>(k);
}

std::vector<FeatureMatch> FeatureTracker::FollowFeatures(const cv::Mat& grey, int frame_index,
                                                         std::vector<cv::Point2f>* points) {
  const cv::Size window(options_.lk_window_px, options_.lk_window_px);
  std::vector<cv::Mat> pyramid;
  cv::buildOpticalFlowPyramid(FollowedImage(grey), pyramid, window, options_.lk_pyramid_levels);
  const RoundTripFlow flow = TrackThereAndBack(follow_pyramid_, pyramid, follow_points_,
                                               options_.lk_window_px, options_.lk_pyramid_levels);
  // A followed feature stays while it returns to where it came from and stays inside the view
  // its corners were detected in.
  std::vector<cv::Point2f> kept;
  std::vector<int> kept_feature;
  std::vector<FeatureMatch> matches;
  for (std::size_t i = 0; i < follow_points_.size(); ++i) {
    if (flow.round_trip_px[i] > options_.lk_max_round_trip_px) continue;
    const int x = static_cast<int>(std::lround(flow.forward[i].x));
    const int y = static_cast<int>(std::lround(flow.forward[i].y));
    if (x < 0 || y < 0 || x >= grey.cols || y >= grey.rows || !detection_mask_.at<uchar>(y, x))
      continue;
    matches.push_back({follow_feature_[i], static_cast<int>(kept.size()), 1.0f});
    kept.push_back(flow.forward[i]);
    kept_feature.push_back(follow_feature_[i]);
  }
  follow_pyramid_ = std::move(pyramid);
  follow_pyramid_frame_ = frame_index;
  follow_points_ = kept;
  follow_feature_ = std::move(kept_feature);
  *points = std::move(kept);
  return matches;
}

TrackingStep FeatureTracker::Track(const cv::Mat& grey, int frame_index,
                                   TrackedKeyframe* keyframe) {
  TrackingStep step;
  const bool follow = options_.matcher == kLucasKanadeMatcher;
  if (!last_) {
    std::vector<TrackedFeature> features;
    for (const cv::Point2f& point : Detect(grey)) {
      TrackedFeature feature;
      if (!Bearing(point, &feature.bearing)) continue;
      feature.track_id = next_track_id_++;
      feature.pixel = point;
      features.push_back(feature);
    }
    *keyframe = TrackedKeyframe();
    MakeKeyframe(grey, frame_index, std::move(features), keyframe);
    step.keyframe = true;
    step.correspondence_fraction = 1.0;
    return step;
  }

  // The frame's points and their matches to the key frame's features: followed, or detected
  // and matched by their templates.
  std::vector<cv::Point2f> points;
  cv::Mat descriptors;
  std::vector<FeatureMatch> matches;
  if (follow) {
    matches = FollowFeatures(grey, frame_index, &points);
  } else {
    points = Detect(grey);
    descriptors = ComputeTemplateDescriptors(grey, points, options_.descriptor);
    matches = MatchByCosineSimilarity(last_->descriptors, last_->points, descriptors, points,
                                      options_.matching);
  }
  std::vector<Eigen::Vector3d> bearings_i, bearings_j;
  std::vector<FeatureMatch> usable_matches;
  for (const FeatureMatch& match : matches) {
    Eigen::Vector3d bearing_j;
    if (!Bearing(points[match.index_b], &bearing_j)) continue;
    bearings_i.push_back(last_->features[match.index_a].bearing);
    bearings_j.push_back(bearing_j);
    usable_matches.push_back(match);
  }
  // The last key-frame step is the motion prior (a crawler moves smoothly along the pipe).
  std::vector<Eigen::Matrix3d> priors;
  if (last_motion_) priors.push_back(last_motion_->essential);
  const SphereRelativePose pose =
      EstimateSphereRelativePose(bearings_i, bearings_j, options_.relative_pose, priors);
  step.inliers = pose.num_inliers;
  if (!pose.success || pose.num_inliers < options_.min_inliers) {
    step.usable = false;
    step.failure = "only " + std::to_string(pose.num_inliers) + " of " +
                   std::to_string(usable_matches.size()) +
                   (follow ? " followed features" : " template matches") +
                   " agree with one relative pose";
    return step;
  }
  std::vector<double> flows;
  for (std::size_t k = 0; k < usable_matches.size(); ++k) {
    if (!pose.inliers[k]) continue;
    flows.push_back(
        cv::norm(last_->points[usable_matches[k].index_a] - points[usable_matches[k].index_b]));
  }
  step.median_flow_px = UpperMedian(flows);
  if (span_start_inliers_ == 0) span_start_inliers_ = pose.num_inliers;
  step.correspondence_fraction = static_cast<double>(pose.num_inliers) / span_start_inliers_;
  step.keyframe = FlowEndsSpan(step.median_flow_px, frame_index - last_->frame_index) ||
                  step.correspondence_fraction < options_.min_correspondence_fraction;
  if (!step.keyframe) return step;

  // The new key frame: inlier template matches keep their track ids ...
  std::vector<TrackedFeature> features;
  std::vector<int> detection_rows;  // per feature: its row of `descriptors`, -1 for guided
  std::vector<char> matched_i(last_->features.size(), 0);
  std::vector<char> used_j(points.size(), 0);
  for (std::size_t k = 0; k < usable_matches.size(); ++k) {
    if (!pose.inliers[k]) continue;
    const FeatureMatch& match = usable_matches[k];
    matched_i[match.index_a] = 1;
    used_j[match.index_b] = 1;
    features.push_back(
        {last_->features[match.index_a].track_id, points[match.index_b], bearings_j[k]});
    detection_rows.push_back(match.index_b);
  }
  const int matches_cosine = static_cast<int>(features.size());
  // ... the key frame's unmatched features are searched for by guided ZNCC (Lucas-Kanade
  // already searched for every one) ...
  if (options_.guided_matching && !follow) {
    std::vector<std::size_t> unmatched;
    for (std::size_t i = 0; i < last_->features.size(); ++i) {
      if (!matched_i[i]) unmatched.push_back(i);
    }
    // The searches are independent (read-only images): spread over the cores, gathered in the
    // key frame's feature order, so the result does not depend on the thread count.
    std::vector<GuidedMatch> searches(unmatched.size());
    cv::parallel_for_(
        cv::Range(0, static_cast<int>(unmatched.size())), [&](const cv::Range& range) {
          for (int u = range.start; u < range.end; ++u) {
            const TrackedFeature& feature = last_->features[unmatched[u]];
            searches[u] = GuidedZnccSearch(last_->grey, grey, feature.pixel, feature.bearing,
                                           pose.essential, bearings_, options_.guided);
          }
        });
    for (std::size_t u = 0; u < unmatched.size(); ++u) {
      const TrackedFeature& feature = last_->features[unmatched[u]];
      const GuidedMatch& guided = searches[u];
      if (!guided.found) continue;
      const int x = static_cast<int>(std::lround(guided.point_j.x));
      const int y = static_cast<int>(std::lround(guided.point_j.y));
      if (x < 0 || y < 0 || x >= grey.cols || y >= grey.rows || !detection_mask_.at<uchar>(y, x))
        continue;
      TrackedFeature tracked{feature.track_id, guided.point_j, Eigen::Vector3d()};
      if (!Bearing(guided.point_j, &tracked.bearing)) continue;
      features.push_back(tracked);
      detection_rows.push_back(-1);
    }
  }
  const int matches_guided = static_cast<int>(features.size()) - matches_cosine;
  // ... and the remaining detections start new tracks, unless they duplicate a tracked one (a
  // template match is a detection itself; a followed feature is not).
  const std::vector<cv::Point2f> detections = follow ? Detect(grey) : points;
  const double duplicate2 = options_.duplicate_radius_px * options_.duplicate_radius_px;
  const std::size_t tracked_count = features.size();
  const std::size_t first_compared = follow ? 0 : matches_cosine;
  // Followed features live long (a median of 1172 carried a key frame on the 8.4 m benchmark,
  // against 179 template matches), so new ones only top each region up to its share
  // (lk_features_per_region): uncapped, 1686 features a key frame took the window adjustments
  // to three times their time.
  const RegionHarrisOptions& regions = options_.harris;
  std::vector<int> region_count(regions.grid_rows * regions.grid_cols, 0);
  const auto region_of = [&](const cv::Point2f& pixel) {
    return RegionCell(regions, grey.size(), static_cast<int>(pixel.x), static_cast<int>(pixel.y));
  };
  if (follow) {
    for (const TrackedFeature& feature : features) ++region_count[region_of(feature.pixel)];
  }
  for (std::size_t j = 0; j < detections.size(); ++j) {
    if (!follow && used_j[j]) continue;
    if (follow && region_count[region_of(detections[j])] >= options_.lk_features_per_region) {
      continue;
    }
    bool duplicate = false;
    for (std::size_t k = first_compared; k < tracked_count && !duplicate; ++k) {
      const cv::Point2f d = features[k].pixel - detections[j];
      duplicate = d.dot(d) < duplicate2;
    }
    if (duplicate) continue;
    TrackedFeature feature{next_track_id_, detections[j], Eigen::Vector3d()};
    if (!Bearing(detections[j], &feature.bearing)) continue;
    ++next_track_id_;
    if (follow) ++region_count[region_of(detections[j])];
    features.push_back(feature);
    detection_rows.push_back(follow ? -1 : static_cast<int>(j));
  }
  *keyframe = TrackedKeyframe();
  keyframe->has_previous = true;
  keyframe->relative_pose = pose;
  last_motion_ = pose;
  keyframe->matches_cosine = matches_cosine;
  keyframe->matches_guided = matches_guided;
  keyframe->median_flow_px = step.median_flow_px;
  recent_flow_per_frame_.push_back(step.median_flow_px /
                                   std::max(1, frame_index - last_->frame_index));
  if (recent_flow_per_frame_.size() > kRecentSpans) {
    recent_flow_per_frame_.erase(recent_flow_per_frame_.begin());
  }
  MakeKeyframe(grey, frame_index, std::move(features), keyframe, descriptors, detection_rows);
  return step;
}

}  // namespace pipescope
