#pragma once

#include <cstddef>
#include <deque>
#include <opencv2/core.hpp>

namespace pipescope {

// One frame's image motion: shift (pixels) and rotation (radians) from the frame before.
struct ImageStep {
  cv::Point2d shift;
  double rotation_rad = 0.0;
};

// Constant-velocity prediction of the next frame's image motion for dense odometry, from the
// median rate of the last few registered pairs, per component: one false registration (a
// marking's edge matched along itself) then neither moves the prediction nor makes the next
// good registration look like a departure from it.
class MotionPredictor {
 public:
  explicit MotionPredictor(std::size_t pairs = 3) : capacity_(pairs) {}

  // A registered pair's motion over `dt` seconds; pairs with dt <= 0 are not rates and are
  // ignored.
  void Add(const ImageStep& step, double dt);
  // Whether any pair has been added.
  bool Known() const { return !rates_.empty(); }
  // The predicted motion over `dt` seconds; zero while nothing is known.
  ImageStep Predict(double dt) const;

 private:
  std::size_t capacity_;
  std::deque<ImageStep> rates_;  // per second, newest last
};

}  // namespace pipescope
