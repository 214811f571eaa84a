#include "pipescope/feature/klt_tracker.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "pipescope/feature/round_trip_flow.h"
#include "pipescope/image/flat_field.h"

namespace pipescope {

KltTracker::KltTracker(const KltTrackerOptions& options) : options_(options) {}

void KltTracker::SetViewMask(const cv::Mat& view_mask) {
  if (view_mask.empty()) {
    inner_view_ = cv::Mat();
    return;
  }
  const int margin =
      static_cast<int>(std::ceil(options_.view_margin_windows * options_.window_px)) + 1;
  cv::erode(view_mask != 0, inner_view_,
            cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * margin + 1, 2 * margin + 1)),
            cv::Point(-1, -1), 1, cv::BORDER_REPLICATE);
}

std::vector<KltPair> KltTracker::Track(const cv::Mat& grey8) {
  std::vector<KltPair> pairs;
  const cv::Size window(options_.window_px, options_.window_px);
  std::vector<cv::Mat> pyramid;
  cv::buildOpticalFlowPyramid(FlatFieldedGrey8(grey8, options_.flat_field_sigma_px), pyramid,
                              window, options_.pyramid_levels);
  if (!points_.empty()) {
    const RoundTripFlow flow = TrackThereAndBack(previous_pyramid_, pyramid, points_,
                                                 options_.window_px, options_.pyramid_levels);
    const float border = static_cast<float>(options_.border_px);
    std::vector<cv::Point2f> kept;
    std::vector<long> kept_ids;
    for (std::size_t i = 0; i < points_.size(); ++i) {
      if (flow.round_trip_px[i] > options_.max_round_trip_px) continue;
      const cv::Point2f& p = flow.forward[i];
      if (p.x < border || p.y < border || p.x > grey8.cols - 1 - border ||
          p.y > grey8.rows - 1 - border) {
        continue;
      }
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
