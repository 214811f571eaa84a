#pragma once

#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <unordered_map>

namespace pipescope {

// The stitching rule of 000 §6.1: each mosaic cell is the mean of all the values the
// contributing (gain-corrected) images put there. Cells live on an unbounded integer plane,
// stored in square tiles allocated when first touched, so a 20 000-cell-long mosaic of which
// frames cover a narrow band costs memory for the band only.
class MeanAccumulator {
 public:
  explicit MeanAccumulator(int tile_size = 256);

  // Adds values(y, x) (CV_32F, one channel) to cell (origin.x + x, origin.y + y) where `mask`
  // (CV_8U, same size; empty = everywhere) is non-zero and the value is finite.
  void Add(const cv::Mat& values, cv::Point origin, const cv::Mat& mask = cv::Mat());

  // Smallest rectangle holding every cell that received a value; empty before any.
  cv::Rect Bounds() const { return bounds_; }

  // The mean over `region` (CV_32F, region's size, (0, 0) = region.tl()), NaN where no value
  // was added.
  cv::Mat Render(const cv::Rect& region) const;

 private:
  struct Tile {
    cv::Mat sum;    // CV_32F
    cv::Mat count;  // CV_32F
  };
  static std::int64_t Key(int tile_x, int tile_y);
  int FloorDiv(int a) const;

  int tile_size_;
  std::unordered_map<std::int64_t, std::unique_ptr<Tile>> tiles_;
  cv::Rect bounds_;
};

}  // namespace pipescope
