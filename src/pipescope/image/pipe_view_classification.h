#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "pipescope/camera/camera.h"

namespace pipescope {

// Straight section or T-intersection, per image (001 §III-B).
enum class PipeViewClass { kStraight = 0, kTIntersection = 1 };

const char* PipeViewClassName(PipeViewClass view_class);

// 001 §III-B: "we expect to see a large round blob near the center of images in straight
// sections". The paper gives no numbers for its empirical thresholds; these defaults were chosen
// on the simulated fiberglass-network preset (docs/fisheye_mapping.md).
struct PipeViewClassificationOptions {
  // Take every `subsample`-th row and column ("sub-sampling pixels from every second row and
  // column").
  int subsample = 2;
  // The lens's half angle of view: pixels farther from the optical axis are not imaged (001's
  // lens covers 190 degrees), even where the model still unprojects them.
  double max_view_angle_deg = 95.0;
  // A field-of-view pixel is dark when its grey level is below this fraction of the median grey
  // level in the field of view (relative, so that exposure changes do not move it).
  double dark_fraction_of_median = 0.4;
  // Binary erosion with a square of this side (half-resolution pixels), before clustering.
  int erosion_size_px = 3;
  // Straight when L_p / L is below this (L: second moment of area of the largest blob about its
  // centroid, L_p: about the principal point).
  double max_straight_moment_ratio = 1.5;
  // A largest blob smaller than this fraction of the field of view is no blob at all: the far
  // pipe is hidden (T) -- classified as T-intersection.
  double min_blob_fraction = 0.002;
};

// What one image's classification saw.
struct PipeViewMeasurement {
  PipeViewClass view_class = PipeViewClass::kStraight;
  double moment_ratio = 0.0;  // L_p / L (infinity when there is no blob)
  int blob_area_px = 0;       // at the reduced resolution
  cv::Point2d blob_centroid;  // full-resolution pixels
};

// Classifies images of one camera; the field-of-view mask and the principal point are computed
// once.
class PipeViewClassifier {
 public:
  PipeViewClassifier(const Camera& camera, const PipeViewClassificationOptions& options = {});

  // `grey`: the camera's size, CV_32F or CV_8U grey levels.
  PipeViewMeasurement Classify(const cv::Mat& grey) const;

  // The reduced-resolution dark blobs after erosion (CV_8U, 255 = dark), for figures and tests.
  cv::Mat DarkBlobMask(const cv::Mat& grey) const;

 private:
  PipeViewClassificationOptions options_;
  cv::Mat fov_mask_;          // CV_8U at the reduced resolution, 255 = inside the field of view
  cv::Point2d principal_px_;  // at the reduced resolution
  int fov_pixels_ = 0;
};

// 001 §III-B / Fig. 3d: temporal filtering that enforces a minimum cluster size: the shortest
// run of equal classes that is shorter than `min_cluster_size` takes its neighbours' class
// (the longer neighbour's when they differ), repeated until every run is long enough or one run
// is left.
std::vector<PipeViewClass> FilterPipeViewClasses(const std::vector<PipeViewClass>& classes,
                                                 int min_cluster_size);

// How many leading classes of `classes` are settled: FilterPipeViewClasses gives them the same
// filtered classes however the sequence continues. A run at least `min_cluster_size` long is
// never merged away and only separates the merges on either side of it (a merge flips one run
// between two of the other class), so everything up to the end of the last such run is
// settled. Lets the odometry start on a straight section while the tracking goes on.
int SettledPipeViewClassCount(const std::vector<PipeViewClass>& classes, int min_cluster_size);

// A strip image like 001 Fig. 3d: one column per key frame (scaled to `width_px`), the initial
// classes on top and the filtered ones below; straight is light grey, T-intersection black.
cv::Mat DrawClassificationStrip(const std::vector<PipeViewClass>& initial,
                                const std::vector<PipeViewClass>& filtered, int width_px = 800,
                                int row_height_px = 24);

}  // namespace pipescope
