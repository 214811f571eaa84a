#include "pipescope/dense/motion_prediction.h"

#include <gtest/gtest.h>

namespace pipescope {
namespace {

TEST(MotionPredictor, PredictsNothingUntilAPairIsKnown) {
  MotionPredictor predictor;
  EXPECT_FALSE(predictor.Known());
  EXPECT_EQ(predictor.Predict(0.1).shift, cv::Point2d(0.0, 0.0));
  predictor.Add({{3.0, 1.0}, 0.02}, 0.0);  // no time step: not a rate
  EXPECT_FALSE(predictor.Known());
}

TEST(MotionPredictor, ScalesTheRateToTheTimeStep) {
  MotionPredictor predictor;
  predictor.Add({{3.0, -1.0}, 0.01}, 1.0 / 30.0);
  ASSERT_TRUE(predictor.Known());
  const ImageStep step = predictor.Predict(2.0 / 30.0);  // a dropped frame: twice the motion
  EXPECT_NEAR(step.shift.x, 6.0, 1e-12);
  EXPECT_NEAR(step.shift.y, -2.0, 1e-12);
  EXPECT_NEAR(step.rotation_rad, 0.02, 1e-12);
}

TEST(MotionPredictor, OneOutlyingPairDoesNotMoveThePrediction) {
  MotionPredictor predictor;  // the median of the last three
  const double dt = 1.0 / 30.0;
  predictor.Add({{-5.0, 0.1}, 0.0}, dt);
  predictor.Add({{-5.2, 0.0}, 0.0}, dt);
  predictor.Add({{20.0, 13.0}, 0.3}, dt);  // a false registration
  ImageStep step = predictor.Predict(dt);
  EXPECT_NEAR(step.shift.x, -5.0, 1e-12);
  EXPECT_NEAR(step.shift.y, 0.1, 1e-12);
  EXPECT_NEAR(step.rotation_rad, 0.0, 1e-12);
  // A real change of speed takes over once it is the majority of the last three.
  predictor.Add({{5.0, 0.0}, 0.0}, dt);
  EXPECT_NEAR(predictor.Predict(dt).shift.x, 5.0, 1e-12);  // of -5.2, 20, 5
  predictor.Add({{5.1, 0.0}, 0.0}, dt);
  EXPECT_NEAR(predictor.Predict(dt).shift.x, 5.1, 1e-12);  // of 20, 5, 5.1
}

TEST(MotionPredictor, AnEvenCountTakesTheMiddleTwosMean) {
  MotionPredictor predictor(4);
  for (double x : {1.0, 2.0, 10.0, 3.0}) predictor.Add({{x, 0.0}, 0.0}, 1.0);
  EXPECT_NEAR(predictor.Predict(1.0).shift.x, 2.5, 1e-12);
}

}  // namespace
}  // namespace pipescope
