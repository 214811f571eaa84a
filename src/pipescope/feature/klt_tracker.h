#pragma once

#include <opencv2/core.hpp>
#include <vector>

namespace pipescope {

// Frame-to-frame feature tracking for the tubular EKF (004 §4 detects and matches features; a
// filter that updates every frame needs the pairs of consecutive frames, which pyramidal
// Lucas-Kanade gives at a fraction of the cost of descriptor matching). Corners are spread over
// a grid so every part of the wall speaks (004 §4: "an unbalanced number of features around the
// camera" biases the rotation), and a track survives only if tracking back lands where it came
// from.
struct KltTrackerOptions {
  int max_features = 160;
  // Grid of cells over the image; each cell is topped up to max_features / cells.
  int grid_cols = 8;
  int grid_rows = 6;
  // cv::goodFeaturesToTrack: minimum eigenvalue relative to the cell's best, and spacing.
  double quality_level = 0.01;
  double min_distance_px = 10.0;
  // cv::calcOpticalFlowPyrLK.
  int window_px = 21;
  int pyramid_levels = 3;
  // Forward-backward check: the backward track must return within this distance.
  double max_round_trip_px = 0.5;
  // Features closer than this to the border are dropped.
  int border_px = 8;
  // Pixels darker than this (grey levels) take no new corners: the unlit depth of a forward view.
  double min_grey = 12.0;
  // Lucas-Kanade tracks a flat-fielded image: the frame divided by its Gaussian blur of this
  // sigma (px; 0 = the frame itself). The lights move with the camera, so the wall's shading
  // stays where it is in the image while the texture moves; where the gain mask does not cancel
  // it (a forward view of a bend, a camera off the axis) it drags every track towards zero flow.
  // On the rendered tube-bend the tracks fell 0.06-0.09 px a frame short of the true flow in
  // the bend; with the shading taken out, within 0.015 px (docs/ekf.md). The sigma must exceed
  // the texture's scale: the low frequencies it removes are lost to the tracker.
  double flat_field_sigma_px = 0.0;
  // How far inside the view mask's edge (SetViewMask) corners are taken and tracks kept, in
  // Lucas-Kanade windows. The edge of a fisheye's image circle stays put in the image while the
  // wall moves, and a window that reaches it is held there: the pyramid's coarser levels see it
  // from farther still, and a track held both ways passes the round trip. On the 190-degree
  // tube-bend at half a window, the tracks 10-12 px inside the edge (90-91 degrees off the axis)
  // moved a median 0.03 of the true flow; a window's width keeps them out. One and a half: the
  // tracks between one and one and a half windows in (85-90 degrees) still fell 1-2 % short of the
  // true flow, where the gain mask falls steeply to the edge (the shading it leaves, or the dark
  // rim it multiplies), which put the distances 0.8-1.4 % short (docs/ekf.md).
  double view_margin_windows = 1.5;
};

struct KltPair {
  cv::Point2f previous;
  cv::Point2f current;
  long track_id = 0;
};

class KltTracker {
 public:
  explicit KltTracker(const KltTrackerOptions& options = {});

  // The pixels the camera sees (CV_8U, non-zero; the frame's size). Outside a fisheye's image
  // circle a frame holds only noise (which the gain mask multiplies), and corners found there
  // track nothing on the wall. No corner is taken, and no track kept, within view_margin_windows
  // Lucas-Kanade windows of the mask's edge (the image's own border is not an edge of the mask).
  // Empty (the default): every pixel.
  void SetViewMask(const cv::Mat& view_mask);

  // Tracks the previous frame's corners into `grey8` (CV_8U) and returns the pairs that passed
  // the round trip; then tops the corners up for the next frame. The first call returns none.
  std::vector<KltPair> Track(const cv::Mat& grey8);

 private:
  void TopUp(const cv::Mat& grey8);

  KltTrackerOptions options_;
  cv::Mat inner_view_;  // SetViewMask's mask shrunk by the margin; empty = every pixel
  std::vector<cv::Mat> previous_pyramid_;
  cv::Mat previous_;
  std::vector<cv::Point2f> points_;
  std::vector<long> ids_;
  long next_id_ = 0;
};

}  // namespace pipescope
