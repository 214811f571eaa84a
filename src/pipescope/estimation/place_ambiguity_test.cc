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

// The neighbours match nearly as well as the right place but lie within the separation: only the
// repeat counts, and at 45 of 80 inliers the right place stands out.
TEST(PlaceAmbiguity, TheRunnerUpIsTheRepeatNotTheNeighbour) {
  const std::vector<PlaceMatch> places = RepeatedWall(80, 45);
  const PlaceJudgement judgement = JudgeBestPlace(places, 2, 0.5, 0.8);
  EXPECT_EQ(judgement.runner_up, 5);
  EXPECT_FALSE(judgement.ambiguous);
  // Closer than the neighbours' spacing, the neighbour is the runner-up, and too close a match.
  const PlaceJudgement near = JudgeBestPlace(places, 2, 0.05, 0.8);
  EXPECT_EQ(near.runner_up, 3);
  EXPECT_TRUE(near.ambiguous);
}

// Best at the repeat (4.0 m, 50 inliers): the right place (3.0 m, 40) is its runner-up, at
// exactly 0.8 of its inliers: ambiguous at 0.8, not at 0.85.
TEST(PlaceAmbiguity, ARepeatThatBarelyWinsIsAmbiguous) {
  const std::vector<PlaceMatch> places = RepeatedWall(40, 50);
  const PlaceJudgement judgement = JudgeBestPlace(places, 5, 0.5, 0.8);
  EXPECT_EQ(judgement.runner_up, 2);
  EXPECT_TRUE(judgement.ambiguous);
  EXPECT_FALSE(JudgeBestPlace(places, 5, 0.5, 0.85).ambiguous);
}

TEST(PlaceAmbiguity, NoOtherPlaceFarEnoughIsNotAmbiguous) {
  const std::vector<PlaceMatch> places = {{1.0, 30}, {1.1, 29}, {1.2, 25}};
  const PlaceJudgement judgement = JudgeBestPlace(places, 0, 0.5, 0.8);
  EXPECT_EQ(judgement.runner_up, -1);
  EXPECT_FALSE(judgement.ambiguous);
  EXPECT_THROW(JudgeBestPlace(places, 3, 0.5, 0.8), std::invalid_argument);
  EXPECT_THROW(JudgeBestPlace({}, 0, 0.5, 0.8), std::invalid_argument);
}

}  // namespace
}  // namespace pipescope
