#include "pipescope/pipeline/travel_direction.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <opencv2/calib3d.hpp>
#include <optional>
#include <vector>

#include "pipescope/image/gain_mask.h"
#include "pipescope/image/undistortion.h"
#include "pipescope/io/image_source.h"

namespace pipescope {
namespace {

// The bearings of the tracks that `pairs` continue from the reference frame (`origins`): where
// each was then and is now.
struct BearingPairs {
  std::vector<Eigen::Vector3d> then, now;
};

BearingPairs Continued(const Camera& camera, const std::map<long, cv::Point2f>& origins,
                       const std::vector<KltPair>& pairs) {
  BearingPairs bearings;
  for (const KltPair& pair : pairs) {
    const auto origin = origins.find(pair.track_id);
    Eigen::Vector3d a, b;
    if (origin == origins.end() ||
        !camera.Unproject(Eigen::Vector2d(origin->second.x, origin->second.y), &a) ||
        !camera.Unproject(Eigen::Vector2d(pair.current.x, pair.current.y), &b)) {
      continue;
    }
    bearings.then.push_back(a.normalized());
    bearings.now.push_back(b.normalized());
  }
  return bearings;
}

// Median angle (rad) between the bearings then and now.
double MedianParallax(const BearingPairs& bearings) {
  std::vector<double> moved;
  for (std::size_t i = 0; i < bearings.then.size(); ++i) {
    moved.push_back(std::acos(std::clamp(bearings.then[i].dot(bearings.now[i]), -1.0, 1.0)));
  }
  if (moved.empty()) return 0.0;
  std::nth_element(moved.begin(), moved.begin() + moved.size() / 2, moved.end());
  return moved[moved.size() / 2];
}

}  // namespace

TravelDirection MeasureTravelDirection(const DatasetManifest& manifest, const Camera& camera,
                                       const cv::Mat& gain_mask, const cv::Mat& view,
                                       const KltTrackerOptions& tracker_options,
                                       const TravelDirectionOptions& options) {
  TravelDirection result;
  KltTracker tracker(tracker_options);
  tracker.SetViewMask(view);
  auto source = ImageSource::Open(manifest, {camera.Width(), camera.Height()});
  // The reference frame's corners: where each track was when the motion began.
  std::map<long, cv::Point2f> origins;
  std::size_t reference = 0;
  const double focal = CentralFocalLengthPx(camera);
  const double min_parallax_rad = options.min_parallax_deg * M_PI / 180.0;
  int frames = 0;
  for (; frames < options.max_frames; ++frames) {
    std::optional<Frame> frame = source->Next();
    if (!frame) break;
    cv::Mat grey8;
    (gain_mask.empty() ? frame->grey : ApplyGainMask(frame->grey, gain_mask))
        .convertTo(grey8, CV_8U);
    const std::vector<KltPair> pairs = tracker.Track(grey8);
    const BearingPairs bearings = Continued(camera, origins, pairs);
    if (origins.empty() || static_cast<int>(bearings.then.size()) < options.min_tracks) {
      // Start again from this frame: its tracks (continued and new) are the origins.
      origins.clear();
      for (const KltPair& pair : pairs) origins[pair.track_id] = pair.current;
      reference = frame->index;
      continue;
    }
    if (MedianParallax(bearings) < min_parallax_rad) continue;
    // The essential matrix on the normalised image plane: the bearings in front of the camera.
    std::vector<cv::Point2d> first, second;
    for (std::size_t i = 0; i < bearings.then.size(); ++i) {
      const Eigen::Vector3d& a = bearings.then[i];
      const Eigen::Vector3d& b = bearings.now[i];
      if (a.z() <= 0.0 || b.z() <= 0.0) continue;
      first.emplace_back(a.x() / a.z(), a.y() / a.z());
      second.emplace_back(b.x() / b.z(), b.y() / b.z());
    }
    if (static_cast<int>(first.size()) < options.min_tracks) continue;
    cv::Mat inlier_mask;
    const cv::Mat essential =
        cv::findEssentialMat(first, second, cv::Mat::eye(3, 3, CV_64F), cv::RANSAC, 0.999,
                             options.ransac_threshold_px / focal, inlier_mask);
    if (essential.rows != 3 || essential.cols != 3) continue;
    cv::Mat rotation, translation;
    const int inliers = cv::recoverPose(essential, first, second, cv::Mat::eye(3, 3, CV_64F),
                                        rotation, translation, inlier_mask);
    if (inliers < options.min_tracks) continue;
    // x2 = R x1 + t: the second camera's centre, in the first camera's frame, is -R^T t.
    const cv::Mat centre = -rotation.t() * translation;
    result.direction =
        Eigen::Vector3d(centre.at<double>(0), centre.at<double>(1), centre.at<double>(2))
            .normalized();
    result.found = true;
    result.reference_frame = reference;
    result.frame = frame->index;
    result.inliers = inliers;
    return result;
  }
  result.failure = fmt::format(
      "the tracks of the first {} frames did not turn {:.1f} degrees with {} tracks in common and "
      "an essential matrix",
      frames, options.min_parallax_deg, options.min_tracks);
  return result;
}

}  // namespace pipescope
