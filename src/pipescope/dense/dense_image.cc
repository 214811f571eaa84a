#include "pipescope/dense/dense_image.h"

#include <algorithm>
#include <opencv2/imgproc.hpp>

#include "pipescope/util/error.h"

namespace pipescope {
namespace {

std::string SizeString(const cv::Mat& image) {
  return std::to_string(image.cols) + "x" + std::to_string(image.rows);
}

void ToFloat(const cv::Mat& image, cv::Mat* image_float) {
  if (image.type() == CV_32FC1) {
    *image_float = image;
  } else {
    image.convertTo(*image_float, CV_32F);
  }
}

}  // namespace

void PrepareRegistrationPair(const cv::Mat& reference, const cv::Mat& next, const std::string& what,
                             cv::Mat* reference_float, cv::Mat* next_float) {
  if (reference.empty() || next.empty()) throw InputError(what + ": an image of the pair is empty");
  if (reference.channels() != 1 || next.channels() != 1) {
    throw InputError(what + ": images must have one channel, got " +
                     std::to_string(reference.channels()) + " and " +
                     std::to_string(next.channels()));
  }
  if (reference.size() != next.size()) {
    throw InputError(what + ": images differ in size: " + SizeString(reference) + " and " +
                     SizeString(next));
  }
  ToFloat(reference, reference_float);
  ToFloat(next, next_float);
}

cv::Rect OverlapAtShift(cv::Size size, cv::Point shift) {
  return cv::Rect(-shift, size) & cv::Rect(cv::Point(0, 0), size);
}

int NumPyramidLevels(cv::Size size, int max_levels, int min_size_px) {
  int levels = 1;
  int shorter = std::min(size.width, size.height);
  while (levels < max_levels && shorter / 2 >= min_size_px) {
    shorter /= 2;
    ++levels;
  }
  return levels;
}

std::vector<cv::Mat> BuildGaussianPyramid(const cv::Mat& image, int num_levels) {
  std::vector<cv::Mat> pyramid{image};
  for (int level = 1; level < num_levels; ++level) {
    cv::Mat coarser;
    cv::pyrDown(pyramid.back(), coarser);
    pyramid.push_back(coarser);
  }
  return pyramid;
}

}  // namespace pipescope
