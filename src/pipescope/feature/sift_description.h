#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "pipescope/feature/region_harris.h"

namespace pipescope {

// 128-D SIFT descriptors (OpenCV) at given keypoints (000 §5.1), upright: the camera barely
// turns between key frames, so no orientation is assigned.
struct SiftDescriptionOptions {
  // Keypoint diameter handed to OpenCV; the described patch is about 5 times as wide.
  float keypoint_size_px = 6.0f;
};

// One row (CV_32F, 128 columns) per keypoint of the image `grey` (one channel, any depth and
// range: it is stretched to 8 bits first, which SIFT's normalisation makes harmless).
cv::Mat DescribeWithSift(const cv::Mat& grey, const std::vector<Keypoint>& keypoints,
                         const SiftDescriptionOptions& options);

}  // namespace pipescope
