#include "pipescope/feature/sift_description.h"

#include <opencv2/features2d.hpp>

#include "pipescope/util/error.h"

namespace pipescope {

cv::Mat DescribeWithSift(const cv::Mat& grey, const std::vector<Keypoint>& keypoints,
                         const SiftDescriptionOptions& options) {
  cv::Mat grey8;
  cv::normalize(grey, grey8, 0, 255, cv::NORM_MINMAX, CV_8U);
  std::vector<cv::KeyPoint> cv_keypoints;
  cv_keypoints.reserve(keypoints.size());
  // Octave 0, layer 0: OpenCV builds one octave from the image itself (no upsampling).
  for (const Keypoint& keypoint : keypoints) {
    cv_keypoints.emplace_back(keypoint.position, options.keypoint_size_px, 0.f, keypoint.response,
                              0);
  }
  // One layer per octave: OpenCV then blurs 4 images instead of 6 for the one octave it builds;
  // the descriptors come from layer 0 either way.
  static thread_local cv::Ptr<cv::SIFT> sift = cv::SIFT::create(0, 1);
  cv::Mat descriptors;
  const std::size_t requested = cv_keypoints.size();
  sift->compute(grey8, cv_keypoints, descriptors);
  if (cv_keypoints.size() != requested) {
    // OpenCV drops keypoints it cannot describe; ours are away from the border, so this is a bug.
    throw std::logic_error("DescribeWithSift: OpenCV dropped keypoints");
  }
  return descriptors;
}

}  // namespace pipescope
