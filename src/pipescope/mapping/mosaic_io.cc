#include "pipescope/mapping/mosaic_io.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "pipescope/util/atomic_file.h"
#include "pipescope/util/error.h"

namespace pipescope {
namespace {

// Percentile q in [0, 1] of `values`, interpolating linearly between order statistics.
double Percentile(std::vector<float>* values, double q) {
  const double position = q * (values->size() - 1);
  const std::size_t below = static_cast<std::size_t>(std::floor(position));
  const std::size_t above = std::min(below + 1, values->size() - 1);
  std::nth_element(values->begin(), values->begin() + below, values->end());
  const double low = (*values)[below];
  // The next order statistic is the smallest value after the nth element.
  const double high =
      above == below ? low : *std::min_element(values->begin() + below + 1, values->end());
  return low + (position - below) * (high - low);
}

}  // namespace

cv::Mat MosaicToGrey8(const cv::Mat& mosaic) {
  CV_Assert(mosaic.type() == CV_32F);
  std::vector<float> covered;
  for (int y = 0; y < mosaic.rows; ++y) {
    const float* row = mosaic.ptr<float>(y);
    for (int x = 0; x < mosaic.cols; ++x) {
      if (std::isfinite(row[x])) covered.push_back(row[x]);
    }
  }
  cv::Mat grey = cv::Mat::zeros(mosaic.size(), CV_8U);
  if (covered.empty()) return grey;
  const double low = Percentile(&covered, 0.005);
  const double high = Percentile(&covered, 0.995);
  const double scale = high > low ? 255.0 / (high - low) : 0.0;
  for (int y = 0; y < mosaic.rows; ++y) {
    const float* row = mosaic.ptr<float>(y);
    uchar* out = grey.ptr<uchar>(y);
    for (int x = 0; x < mosaic.cols; ++x) {
      if (!std::isfinite(row[x])) continue;
      out[x] = high > low ? cv::saturate_cast<uchar>((row[x] - low) * scale) : 128;
    }
  }
  return grey;
}

void WriteMosaicPng(const std::filesystem::path& path, const cv::Mat& mosaic) {
  const cv::Mat grey = MosaicToGrey8(mosaic);
  WriteFileAtomically(path, [&](const std::filesystem::path& temporary) {
    if (!cv::imwrite(temporary.string(), grey)) {
      throw InputError("cannot write mosaic " + path.string());
    }
  });
}

}  // namespace pipescope
