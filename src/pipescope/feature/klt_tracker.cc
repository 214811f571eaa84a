#include "pipescope/feature/klt_tracker.h"

#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

namespace pipescope {

KltTracker::KltTracker(const KltTrackerOptions& options) : options_(options) {}

void KltTracker::SetViewMask(const cv::Mat& view_mask) {
  if (view_mask.empty()) {
    inner_view_ = cv::Mat();
    return;
  }
  const int half = options_.window_px / 2 + 1;
  cv::erode(view_mask != 0, inner_view_,
            cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * half + 1, 2 * half + 1)),
            cv::Point(-1, -1), 1, cv::BORDER_REPLICATE);
}

std::vector<KltPair> KltTracker::Track(const cv::Mat& grey8) {
  std::vector<KltPair> pairs;
  const cv::Size window(options_.window_px, options_.window_px);
  std::vector<cv::Mat> pyramid;
  cv::buildOpticalFlowPyramid(TrackedImage(grey8), pyramid, window, options_.pyramid_levels);
  if (!points_.empty()) {
    std::vector<cv::Point2f> forward, backward;
    std::vector<unsigned char> status_forward, status_backward;
    std::vector<float> error;
    cv::calcOpticalFlowPyrLK(previous_pyramid_, pyramid, points_, forward, status_forward, error,
                             window, options_.pyramid_levels);
    backward = points_;
    cv::calcOpticalFlowPyrLK(
        pyramid, previous_pyramid_, forward, backward, status_backward, error, window,
        options_.pyramid_levels,
        cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 30, 0.01),
        cv::OPTFLOW_USE_INITIAL_FLOW);
    const float border = static_cast<float>(options_.border_px);
    std::vector<cv::Point2f> kept;
    std::vector<long> kept_ids;
    for (std::size_t i = 0; i < points_.size(); ++i) {
      if (!status_forward[i] || !status_backward[i]) continue;
      const cv::Point2f& p = forward[i];
      if (p.x < border || p.y < border || p.x > grey8.cols - 1 - border ||
          p.y > grey8.rows - 1 - border) {
        continue;
      }
      if (cv::norm(backward[i] - points_[i]) > options_.max_round_trip_px) continue;
      if (!inner_view_.empty() && inner_view_.at<uchar>(cvRound(p.y), cvRound(p.x)) == 0) {
        continue;
      }
      pairs.push_back({points_[i], p, ids_[i]});
      kept.push_back(p);
      kept_ids.push_back(ids_[i]);
    }
    points_ = std::move(kept);
    ids_ = std::move(kept_ids);
  }
  TopUp(grey8);
  previous_pyramid_ = std::move(pyramid);
  previous_ = grey8;
  return pairs;
}

cv::Mat KltTracker::TrackedImage(const cv::Mat& grey8) const {
  const double sigma = options_.flat_field_sigma_px;
  if (sigma <= 0.0) return grey8;
  cv::Mat grey;
  grey8.convertTo(grey, CV_32F);
  // The shading is smooth: blur a quarter-size copy and bring it back, a sixteenth of the cost of
  // a full-size blur with a kernel this wide.
  const int shrink = sigma >= 8.0 ? 4 : 1;
  cv::Mat small, shading;
  cv::resize(grey, small, cv::Size(grey.cols / shrink, grey.rows / shrink), 0, 0, cv::INTER_AREA);
  cv::GaussianBlur(small, small, cv::Size(), sigma / shrink);
  cv::resize(small, shading, grey.size(), 0, 0, cv::INTER_LINEAR);
  // Light times albedo: dividing by the shading leaves the albedo, at mid-grey (the floor keeps
  // the unlit depth from amplifying its noise without bound).
  cv::Mat albedo = 128.0 * grey / cv::max(shading, 4.0), tracked;
  albedo.convertTo(tracked, CV_8U);
  return tracked;
}

void KltTracker::TopUp(const cv::Mat& grey8) {
  const int cells = options_.grid_cols * options_.grid_rows;
  const int per_cell = std::max(1, options_.max_features / cells);
  const int cell_w = grey8.cols / options_.grid_cols;
  const int cell_h = grey8.rows / options_.grid_rows;
  std::vector<int> count(cells, 0);
  cv::Mat mask(grey8.size(), CV_8U, cv::Scalar(255));
  mask.setTo(0, grey8 < options_.min_grey);
  if (!inner_view_.empty()) mask.setTo(0, inner_view_ == 0);
  for (const cv::Point2f& p : points_) {
    const int cx = std::min(options_.grid_cols - 1, static_cast<int>(p.x) / cell_w);
    const int cy = std::min(options_.grid_rows - 1, static_cast<int>(p.y) / cell_h);
    ++count[cy * options_.grid_cols + cx];
    cv::circle(mask, p, static_cast<int>(options_.min_distance_px), cv::Scalar(0), -1);
  }
  const int b = options_.border_px;
  for (int cy = 0; cy < options_.grid_rows; ++cy) {
    for (int cx = 0; cx < options_.grid_cols; ++cx) {
      const int wanted = per_cell - count[cy * options_.grid_cols + cx];
      if (wanted <= 0) continue;
      cv::Rect cell(cx * cell_w, cy * cell_h, cell_w, cell_h);
      cell &= cv::Rect(b, b, grey8.cols - 2 * b, grey8.rows - 2 * b);
      if (cell.area() <= 0) continue;
      std::vector<cv::Point2f> corners;
      cv::goodFeaturesToTrack(grey8(cell), corners, wanted, options_.quality_level,
                              options_.min_distance_px, mask(cell));
      for (const cv::Point2f& corner : corners) {
        points_.push_back(corner +
                          cv::Point2f(static_cast<float>(cell.x), static_cast<float>(cell.y)));
        ids_.push_back(next_id_++);
      }
    }
  }
}

}  // namespace pipescope
