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
  // OpenCV's default 3 layers per octave: it blurs the one octave it builds 5 times with small
  // kernels (87 taps in all); one layer would blur it 3 times with sigma 2.8, 5.5 and 11 (157
  // taps). The descriptors come from layer 0 (the base image) either way.
  static thread_local cv::Ptr<cv::SIFT> sift = cv::SIFT::create();
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
