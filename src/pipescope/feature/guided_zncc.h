#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "pipescope/camera/camera.h"

namespace pipescope {

// The unit bearing of every integer pixel of a camera, computed once (001 §III-A back-projects
// each integer pixel to the sphere to bound the epipolar search region). Pixels beyond the
// model's field of view are invalid.
class BearingTable {
 public:
  // Pixels farther than `max_view_angle_rad` from the optical axis are invalid too (the lens's
  // half angle of view, which the model may exceed).
  explicit BearingTable(const Camera& camera, double max_view_angle_rad = 3.2);
  bool Valid(int x, int y) const { return valid_.at<uchar>(y, x) != 0; }
  Eigen::Vector3d At(int x, int y) const {
    const cv::Vec3f& b = bearings_.at<cv::Vec3f>(y, x);
    return Eigen::Vector3d(b[0], b[1], b[2]);
  }
  const cv::Mat& valid_mask() const { return valid_; }
  const cv::Mat& bearing_mat() const { return bearings_; }
  int width() const { return bearings_.cols; }
  int height() const { return bearings_.rows; }

  // The columns x0..x1 of row y whose bearing eta is valid and satisfies |eta . normal| <
  // threshold (the epipolar band of 001 §III-A, normal = E eta_i), ascending, into `band`.
  // Exactly the columns a test of every pixel finds: a chunk of columns whose middle pixel is
  // far enough outside the band is skipped whole, since along a row's valid run each bearing
  // component changes by at most max_column_step_ from one column to the next.
  void EpipolarBandColumns(int y, int x0, int x1, const cv::Vec3f& normal, float threshold,
                           std::vector<int>* band) const;

 private:
  cv::Mat bearings_;  // CV_32FC3
  cv::Mat valid_;     // CV_8U
  // Per row: the valid columns [begin, end) when they are one run; a row with several runs is
  // tested pixel by pixel (run_begin_ = -1).
  std::vector<int> run_begin_, run_end_;
  cv::Vec3f max_column_step_;  // per component, over horizontally adjacent valid pixels
};

// Epipolar-guided ZNCC (001 §III-A): for a feature of image i, the pixel of image j whose
// template best correlates (zero-mean normalised cross-correlation, in the original fisheye
// image), among the integer pixels within `search_radius_px` whose bearing satisfies
// |eta_j^T E eta_i| < epipolar_threshold.
struct GuidedZnccOptions {
  int template_size_px = 11;
  int search_radius_px = 40;
  double epipolar_threshold = 0.006;  // on |eta_j^T E eta_i| with |E|_F = sqrt(2)
  // 0.85 before: on a plain stretch of route B's wall the search then carried 10-45 features a
  // key frame (130-380 elsewhere), the tracks stayed one key frame long, and the windows there
  // failed one after another; at 0.75 twice as many are carried and route B's straight windows
  // hold (2 of 407 rejected, was 144; seed 41, held out: 1, was 138). The guided matches of
  // FisheyeTracking.GuidedMatchesLieWhereTheTruePosesPutThem stay within 1 px of the truth at
  // either value; that clean wall does not tell them apart (docs/fisheye_mapping.md, "Guided
  // matching at ZNCC 0.75").
  double min_zncc = 0.75;
  // The best score must beat the best outside its 3x3 neighbourhood by this margin (a unique
  // peak along the epipolar region).
  double min_peak_margin = 0.02;
};

struct GuidedMatch {
  bool found = false;
  cv::Point2f point_j;  // integer pixel plus a parabolic sub-pixel refinement
  double zncc = 0.0;
};

// `grey_i`, `grey_j`: CV_32F. `essential`: cam_j_from_cam_i, eta_j^T E eta_i = 0.
GuidedMatch GuidedZnccSearch(const cv::Mat& grey_i, const cv::Mat& grey_j,
                             const cv::Point2f& point_i, const Eigen::Vector3d& bearing_i,
                             const Eigen::Matrix3d& essential, const BearingTable& bearings,
                             const GuidedZnccOptions& options = {});

}  // namespace pipescope
