#include "pipescope/dense/motion_prediction.h"

#include <vector>

#include "pipescope/util/median.h"

namespace pipescope {
void MotionPredictor::Add(const ImageStep& step, double dt) {
  if (!(dt > 0.0) || capacity_ == 0) return;
  rates_.push_back({step.shift * (1.0 / dt), step.rotation_rad / dt});
  while (rates_.size() > capacity_) rates_.pop_front();
}

ImageStep MotionPredictor::Predict(double dt) const {
  if (rates_.empty()) return {};
  std::vector<double> x, y, rotation;
  for (const ImageStep& rate : rates_) {
    x.push_back(rate.shift.x);
    y.push_back(rate.shift.y);
    rotation.push_back(rate.rotation_rad);
  }
  return {cv::Point2d(Median(x), Median(y)) * dt, Median(rotation) * dt};
}

}  // namespace pipescope
