#include "pipescope/image/pipe_view_classification.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "pipescope/util/error.h"

namespace pipescope {

const char* PipeViewClassName(PipeViewClass view_class) {
  return view_class == PipeViewClass::kStraight ? "straight" : "t-intersection";
}

PipeViewClassifier::PipeViewClassifier(const Camera& camera,
                                       const PipeViewClassificationOptions& options)
    : options_(options) {
  if (options_.subsample < 1) throw InputError("classification.subsample must be >= 1");
  const int step = options_.subsample;
  const int width = (camera.Width() + step - 1) / step;
  const int height = (camera.Height() + step - 1) / step;
  fov_mask_ = cv::Mat::zeros(height, width, CV_8U);
  Eigen::Vector3d bearing;
  const double min_cos_angle = std::cos(options_.max_view_angle_deg * M_PI / 180.0);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      if (camera.Unproject(Eigen::Vector2d(x * step, y * step), &bearing) &&
          bearing.z() >= min_cos_angle) {
        fov_mask_.at<uchar>(y, x) = 255;
        ++fov_pixels_;
      }
    }
  }
  Eigen::Vector2d principal;
  camera.Project(Eigen::Vector3d(0, 0, 1), &principal);
  principal_px_ = cv::Point2d(principal.x() / step, principal.y() / step);
}

cv::Mat PipeViewClassifier::DarkBlobMask(const cv::Mat& grey) const {
  const int step = options_.subsample;
  cv::Mat reduced(fov_mask_.size(), CV_8U);
  cv::Mat grey8;
  if (grey.depth() == CV_8U) {
    grey8 = grey;
  } else {
    grey.convertTo(grey8, CV_8U);
  }
  for (int y = 0; y < reduced.rows; ++y) {
    for (int x = 0; x < reduced.cols; ++x) {
      reduced.at<uchar>(y, x) = grey8.at<uchar>(y * step, x * step);
    }
  }
  // The median over the field of view, from a histogram.
  int histogram[256] = {};
  for (int y = 0; y < reduced.rows; ++y) {
    for (int x = 0; x < reduced.cols; ++x) {
      if (fov_mask_.at<uchar>(y, x)) ++histogram[reduced.at<uchar>(y, x)];
    }
  }
  int median = 0;
  for (int count = 0; median < 256; ++median) {
    count += histogram[median];
    if (2 * count >= fov_pixels_) break;
  }
  const double threshold = options_.dark_fraction_of_median * median;
  cv::Mat dark = cv::Mat::zeros(reduced.size(), CV_8U);
  for (int y = 0; y < reduced.rows; ++y) {
    for (int x = 0; x < reduced.cols; ++x) {
      if (fov_mask_.at<uchar>(y, x) && reduced.at<uchar>(y, x) < threshold) {
        dark.at<uchar>(y, x) = 255;
      }
    }
  }
  if (options_.erosion_size_px > 1) {
    cv::erode(dark, dark,
              cv::getStructuringElement(
                  cv::MORPH_RECT, cv::Size(options_.erosion_size_px, options_.erosion_size_px)));
  }
  return dark;
}

PipeViewMeasurement PipeViewClassifier::Classify(const cv::Mat& grey) const {
  const cv::Mat dark = DarkBlobMask(grey);
  cv::Mat labels, stats, centroids;
  const int count = cv::connectedComponentsWithStats(dark, labels, stats, centroids, 8, CV_32S);
  int largest = 0;
  for (int label = 1; label < count; ++label) {
    if (largest == 0 ||
        stats.at<int>(label, cv::CC_STAT_AREA) > stats.at<int>(largest, cv::CC_STAT_AREA)) {
      largest = label;
    }
  }
  PipeViewMeasurement measurement;
  measurement.view_class = PipeViewClass::kTIntersection;
  measurement.moment_ratio = std::numeric_limits<double>::infinity();
  if (largest == 0) return measurement;
  measurement.blob_area_px = stats.at<int>(largest, cv::CC_STAT_AREA);
  const double cx = centroids.at<double>(largest, 0);
  const double cy = centroids.at<double>(largest, 1);
  measurement.blob_centroid = cv::Point2d(cx * options_.subsample, cy * options_.subsample);
  // Second moments of area (polar) about the centroid, L, and about the principal point, L_p.
  double moment_centroid = 0.0;
  double moment_principal = 0.0;
  for (int y = 0; y < labels.rows; ++y) {
    const int* row = labels.ptr<int>(y);
    for (int x = 0; x < labels.cols; ++x) {
      if (row[x] != largest) continue;
      moment_centroid += (x - cx) * (x - cx) + (y - cy) * (y - cy);
      moment_principal += (x - principal_px_.x) * (x - principal_px_.x) +
                          (y - principal_px_.y) * (y - principal_px_.y);
    }
  }
  if (measurement.blob_area_px < options_.min_blob_fraction * fov_pixels_ ||
      moment_centroid <= 0.0) {
    return measurement;
  }
  measurement.moment_ratio = moment_principal / moment_centroid;
  measurement.view_class = measurement.moment_ratio < options_.max_straight_moment_ratio
                               ? PipeViewClass::kStraight
                               : PipeViewClass::kTIntersection;
  return measurement;
}

std::vector<PipeViewClass> FilterPipeViewClasses(const std::vector<PipeViewClass>& classes,
                                                 int min_cluster_size) {
  struct Run {
    PipeViewClass view_class;
    int length;
  };
  std::vector<Run> runs;
  for (PipeViewClass view_class : classes) {
    if (!runs.empty() && runs.back().view_class == view_class) {
      ++runs.back().length;
    } else {
      runs.push_back({view_class, 1});
    }
  }
  while (runs.size() > 1) {
    int shortest = 0;
    for (int i = 1; i < static_cast<int>(runs.size()); ++i) {
      if (runs[i].length < runs[shortest].length) shortest = i;
    }
    if (runs[shortest].length >= min_cluster_size) break;
    // Merge into the neighbours: with two classes, both neighbours have the other class.
    const int n = static_cast<int>(runs.size());
    const PipeViewClass other = runs[shortest].view_class == PipeViewClass::kStraight
                                    ? PipeViewClass::kTIntersection
                                    : PipeViewClass::kStraight;
    runs[shortest].view_class = other;
    std::vector<Run> merged;
    for (int i = 0; i < n; ++i) {
      if (!merged.empty() && merged.back().view_class == runs[i].view_class) {
        merged.back().length += runs[i].length;
      } else {
        merged.push_back(runs[i]);
      }
    }
    runs = std::move(merged);
  }
  std::vector<PipeViewClass> filtered;
  filtered.reserve(classes.size());
  for (const Run& run : runs) filtered.insert(filtered.end(), run.length, run.view_class);
  return filtered;
}

int SettledPipeViewClassCount(const std::vector<PipeViewClass>& classes, int min_cluster_size) {
  int run_length = 0;
  int settled = 0;
  for (int k = 0; k < static_cast<int>(classes.size()); ++k) {
    run_length = k > 0 && classes[k] == classes[k - 1] ? run_length + 1 : 1;
    if (run_length >= min_cluster_size) settled = k + 1;
  }
  return settled;
}

cv::Mat DrawClassificationStrip(const std::vector<PipeViewClass>& initial,
                                const std::vector<PipeViewClass>& filtered, int width_px,
                                int row_height_px) {
  const int gap = std::max(2, row_height_px / 4);
  cv::Mat strip(2 * row_height_px + gap, width_px, CV_8U, cv::Scalar(255));
  const auto draw_row = [&](const std::vector<PipeViewClass>& classes, int top) {
    if (classes.empty()) return;
    for (int x = 0; x < width_px; ++x) {
      const std::size_t index =
          std::min(classes.size() - 1,
                   static_cast<std::size_t>(static_cast<double>(x) * classes.size() / width_px));
      const uchar value = classes[index] == PipeViewClass::kStraight ? 200 : 0;
      strip(cv::Rect(x, top, 1, row_height_px)).setTo(value);
    }
  };
  draw_row(initial, 0);
  draw_row(filtered, row_height_px + gap);
  return strip;
}

}  // namespace pipescope
