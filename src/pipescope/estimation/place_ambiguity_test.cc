#include "pipescope/estimation/place_ambiguity.h"

#include <gtest/gtest.h>

namespace pipescope {
namespace {

// A later pass sampled every 0.1 m: the right place at 3.0 m and its neighbours, which see much
// the same wall, and the wall's repeat one metre on.
std::vector<PlaceMatch> RepeatedWall(int right_inliers, int repeat_inliers) {
  return {{2.5, 21}, {2.9, right_inliers - 5}, {3.0, right_inliers},     {3.1, right_inliers - 3},
          {3.5, 22}, {4.0, repeat_inliers},    {4.1, repeat_inliers - 8}};
}

TEST(PlaceAmbiguity, TheRunnerUpIsTheRepeatNotTheNeighbour) {
  const std::vector<PlaceMatch> places = RepeatedWall(80, 45);
  EXPECT_EQ(RunnerUpPlace(places, 2, 0.5), 5);
  // Closer than the neighbours' spacing, the neighbour is the runner-up.
  EXPECT_EQ(RunnerUpPlace(places, 2, 0.05), 3);
}

TEST(PlaceAmbiguity, ThePlaceOnTheOtherSideCountsToo) {
  const std::vector<PlaceMatch> places = RepeatedWall(40, 50);
  // Best at the repeat (4.0 m): the right place (3.0 m) is its runner-up.
  EXPECT_EQ(RunnerUpPlace(places, 5, 0.5), 2);
}

TEST(PlaceAmbiguity, NoOtherPlaceFarEnough) {
  const std::vector<PlaceMatch> places = {{1.0, 30}, {1.1, 29}, {1.2, 25}};
  EXPECT_EQ(RunnerUpPlace(places, 0, 0.5), -1);
  EXPECT_THROW(RunnerUpPlace(places, 3, 0.5), std::invalid_argument);
  EXPECT_THROW(RunnerUpPlace({}, 0, 0.5), std::invalid_argument);
}

}  // namespace
}  // namespace pipescope
