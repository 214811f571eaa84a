#include "pipescope/mapping/mean_accumulator.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pipescope {

MeanAccumulator::MeanAccumulator(int tile_size) : tile_size_(tile_size) {
  CV_Assert(tile_size > 0);
}

std::int64_t MeanAccumulator::Key(int tile_x, int tile_y) {
  return (static_cast<std::int64_t>(tile_y) << 32) ^ static_cast<std::uint32_t>(tile_x);
}

int MeanAccumulator::FloorDiv(int a) const {
  return a >= 0 ? a / tile_size_ : -((-a + tile_size_ - 1) / tile_size_);
}

void MeanAccumulator::Add(const cv::Mat& values, cv::Point origin, const cv::Mat& mask) {
  CV_Assert(values.type() == CV_32F);
  CV_Assert(mask.empty() || (mask.type() == CV_8U && mask.size() == values.size()));
  if (values.empty()) return;
  const cv::Rect area(origin, values.size());
  // Cells that actually receive a value, for the bounds.
  int min_x = std::numeric_limits<int>::max(), min_y = std::numeric_limits<int>::max();
  int max_x = std::numeric_limits<int>::min(), max_y = std::numeric_limits<int>::min();
  for (int tile_y = FloorDiv(area.y); tile_y <= FloorDiv(area.br().y - 1); ++tile_y) {
    for (int tile_x = FloorDiv(area.x); tile_x <= FloorDiv(area.br().x - 1); ++tile_x) {
      const cv::Rect tile_rect(tile_x * tile_size_, tile_y * tile_size_, tile_size_, tile_size_);
      const cv::Rect overlap = tile_rect & area;
      std::unique_ptr<Tile>& tile = tiles_[Key(tile_x, tile_y)];
      bool touched = false;
      for (int y = overlap.y; y < overlap.br().y; ++y) {
        const float* in = values.ptr<float>(y - origin.y);
        const uchar* in_mask = mask.empty() ? nullptr : mask.ptr<uchar>(y - origin.y);
        float* sum = nullptr;
        float* count = nullptr;
        int first_x = std::numeric_limits<int>::max(), last_x = std::numeric_limits<int>::min();
        for (int x = overlap.x; x < overlap.br().x; ++x) {
          const int ix = x - origin.x;
          if ((in_mask != nullptr && in_mask[ix] == 0) || !std::isfinite(in[ix])) continue;
          if (sum == nullptr) {
            if (!tile) {
              tile = std::make_unique<Tile>();
              tile->sum = cv::Mat::zeros(tile_size_, tile_size_, CV_32F);
              tile->count = cv::Mat::zeros(tile_size_, tile_size_, CV_32F);
            }
            sum = tile->sum.ptr<float>(y - tile_rect.y);
            count = tile->count.ptr<float>(y - tile_rect.y);
            first_x = x;
          }
          sum[x - tile_rect.x] += in[ix];
          count[x - tile_rect.x] += 1.0f;
          last_x = x;
        }
        if (sum == nullptr) continue;
        min_x = std::min(min_x, first_x);
        max_x = std::max(max_x, last_x);
        min_y = std::min(min_y, y);
        max_y = std::max(max_y, y);
        touched = true;
      }
      if (!touched && !tile) tiles_.erase(Key(tile_x, tile_y));
    }
  }
  if (min_x > max_x) return;
  const cv::Rect added(min_x, min_y, max_x - min_x + 1, max_y - min_y + 1);
  bounds_ = bounds_.empty() ? added : (bounds_ | added);
}

cv::Mat MeanAccumulator::Render(const cv::Rect& region) const {
  cv::Mat mean(region.size(), CV_32F, cv::Scalar(std::numeric_limits<float>::quiet_NaN()));
  if (region.empty()) return mean;
  for (int tile_y = FloorDiv(region.y); tile_y <= FloorDiv(region.br().y - 1); ++tile_y) {
    for (int tile_x = FloorDiv(region.x); tile_x <= FloorDiv(region.br().x - 1); ++tile_x) {
      const auto it = tiles_.find(Key(tile_x, tile_y));
      if (it == tiles_.end()) continue;
      const Tile& tile = *it->second;
      const cv::Rect tile_rect(tile_x * tile_size_, tile_y * tile_size_, tile_size_, tile_size_);
      const cv::Rect overlap = tile_rect & region;
      for (int y = overlap.y; y < overlap.br().y; ++y) {
        const float* sum = tile.sum.ptr<float>(y - tile_rect.y);
        const float* count = tile.count.ptr<float>(y - tile_rect.y);
        float* out = mean.ptr<float>(y - region.y);
        for (int x = overlap.x; x < overlap.br().x; ++x) {
          const int tx = x - tile_rect.x;
          if (count[tx] > 0.0f) out[x - region.x] = sum[tx] / count[tx];
        }
      }
    }
  }
  return mean;
}

}  // namespace pipescope
