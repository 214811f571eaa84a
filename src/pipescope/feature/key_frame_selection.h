#pragma once

#include <opencv2/core.hpp>
#include <vector>

namespace pipescope {

// Key-frame selection of 000 §5.1 (after Mouragnon et al. and Tardif et al.): frames are matched
// to the last key frame until the correspondences become too few or the median sparse optical
// flow too large; the frame before that one becomes the next key frame.
struct KeyFrameOptions {
  // Fewer inlier correspondences than this end the key frame's span (000 §5.1) ...
  int min_correspondences = 150;
  // ... or, where the texture gives fewer to begin with, fewer than this fraction of those of
  // the span's first frame (beyond 000: on faint, noisy wall the first frame after a key frame
  // has 20-60, the absolute 150 made every frame a key frame, and the short baselines lost the
  // scale; docs/conditions.md). 0: the absolute number alone.
  double min_correspondence_fraction = 0.5;
  // A median flow above this fraction of the image's larger side ends the span.
  double max_median_flow_fraction = 0.15;
};

// Median length of the flow vectors (pixels); 0 for none.
double MedianFlow(const std::vector<cv::Point2f>& from, const std::vector<cv::Point2f>& to);

// Whether a frame with `correspondences` inliers to the key frame and median flow
// `median_flow_px` is too far from it, in an image whose larger side is `image_extent_px`.
// `span_start_correspondences`: those of the span's first frame (0: not known).
bool EndsKeyFrameSpan(int correspondences, int span_start_correspondences, double median_flow_px,
                      int image_extent_px, const KeyFrameOptions& options);

}  // namespace pipescope
