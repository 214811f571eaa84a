#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <string>

#include "pipescope/camera/camera.h"
#include "pipescope/feature/klt_tracker.h"
#include "pipescope/io/dataset.h"

namespace pipescope {

// The direction the camera travels in its own frame at the start of a dataset, measured rather
// than assumed from the mount: a crawler moves along the pipe, so this lies near the pipe's axis
// in the first camera's frame (off it by any sideways motion of the crawler), whether the camera
// looks down the pipe or at its wall. The first frames'
// tracks, once they have moved far enough for the translation to show, give an essential matrix
// (five-point RANSAC, cv::findEssentialMat on the bearings in front of the camera) whose
// translation cv::recoverPose returns.
struct TravelDirectionOptions {
  // Median angle between the tracks' bearings in the reference frame and now before the pose is
  // computed (degrees, so that every lens model is alike). A narrow view tells a translation
  // across it from a turn only by small perspective differences, which grow with the baseline:
  // against the truth, at 6 degrees steel-6in's direction came out 0.6-0.9 degrees off, the
  // 16-inch pipe's 25-degree view 13-18 (at 3 degrees 24-26), the culvert 1.1, tube-bend's
  // forward view 3.7 (5.4 at 320 x 240); at 10 degrees a forward view's tracks seldom lasted
  // long enough.
  double min_parallax_deg = 6.0;
  // The reference frame is renewed when fewer of its tracks than this survive.
  int min_tracks = 30;
  // Give up after this many frames.
  int max_frames = 300;
  // RANSAC threshold on the normalised image plane, in pixels of the central focal length.
  double ransac_threshold_px = 1.0;
};

struct TravelDirection {
  bool found = false;
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();  // unit, the reference camera frame
  std::size_t reference_frame = 0;                       // the frame the motion was measured from
  std::size_t frame = 0;                                 // and to
  int inliers = 0;
  std::string failure;  // why none was found
};

// Reads the dataset's first frames, gain-corrected by `gain_mask` (may be empty) as the filter
// sees them; `view`: the pixels the camera sees (KltTracker::SetViewMask), may be empty.
TravelDirection MeasureTravelDirection(const DatasetManifest& manifest, const Camera& camera,
                                       const cv::Mat& gain_mask, const cv::Mat& view,
                                       const KltTrackerOptions& tracker_options,
                                       const TravelDirectionOptions& options);

}  // namespace pipescope
