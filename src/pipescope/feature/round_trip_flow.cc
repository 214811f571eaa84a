#include "pipescope/feature/round_trip_flow.h"

#include <limits>
#include <opencv2/video/tracking.hpp>

namespace pipescope {

RoundTripFlow TrackThereAndBack(const std::vector<cv::Mat>& previous_pyramid,
                                const std::vector<cv::Mat>& pyramid,
                                const std::vector<cv::Point2f>& points, int window_px,
                                int pyramid_levels, const std::vector<cv::Point2f>* starts) {
  RoundTripFlow flow;
  if (points.empty()) return flow;
  const cv::Size window(window_px, window_px);
  const cv::TermCriteria criteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 30, 0.01);
  std::vector<unsigned char> status_forward, status_backward;
  std::vector<float> error;
  if (starts != nullptr) flow.forward = *starts;
  cv::calcOpticalFlowPyrLK(previous_pyramid, pyramid, points, flow.forward, status_forward, error,
                           window, pyramid_levels, criteria,
                           starts != nullptr ? cv::OPTFLOW_USE_INITIAL_FLOW : 0);
  std::vector<cv::Point2f> backward = points;
  cv::calcOpticalFlowPyrLK(pyramid, previous_pyramid, flow.forward, backward, status_backward,
                           error, window, pyramid_levels, criteria, cv::OPTFLOW_USE_INITIAL_FLOW);
  flow.round_trip_px.resize(points.size(), std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (status_forward[i] && status_backward[i]) {
      flow.round_trip_px[i] = cv::norm(backward[i] - points[i]);
    }
  }
  return flow;
}

}  // namespace pipescope
