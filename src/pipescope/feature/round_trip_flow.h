#pragma once

#include <opencv2/core.hpp>
#include <vector>

namespace pipescope {

// Pyramidal Lucas-Kanade from one frame to the next and back (cv::calcOpticalFlowPyrLK both
// ways): where each point went, and how far tracking it back lands from where it came from
// (infinity where either direction lost it). A track that does not come back is not trusted.
struct RoundTripFlow {
  std::vector<cv::Point2f> forward;
  std::vector<double> round_trip_px;
};

// `starts` (may be null): where each forward search begins in `pyramid` (a match's position, to
// be refined), instead of at the point itself.
RoundTripFlow TrackThereAndBack(const std::vector<cv::Mat>& previous_pyramid,
                                const std::vector<cv::Mat>& pyramid,
                                const std::vector<cv::Point2f>& points, int window_px,
                                int pyramid_levels,
                                const std::vector<cv::Point2f>* starts = nullptr);

}  // namespace pipescope
