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

RoundTripFlow TrackThereAndBack(const std::vector<cv::Mat>& previous_pyramid,
                                const std::vector<cv::Mat>& pyramid,
                                const std::vector<cv::Point2f>& points, int window_px,
                                int pyramid_levels);

}  // namespace pipescope
