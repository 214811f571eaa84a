#include "pipescope/estimation/pass_consensus.h"

#include <gtest/gtest.h>

namespace pipescope {
namespace {

// Route B's second pass of T1-T4 came out at about 0.43 of its length; of eleven PnP-confirmed
// edges six paired places 1-6 m apart (a wall pattern repeating every metre). The five correct
// ones lie on one line earlier = a + b later, and only they are kept.
TEST(PassConsensus, KeepsTheEdgesOnOneLineAndDropsThoseOffByARepeat) {
  // The true places (x along the pipe, m) of that run's eleven edges, earlier and later pass.
  const std::vector<double> earlier = {7.729, 7.358, 7.090, 6.811, 6.628, 7.628,
                                       7.540, 7.451, 6.720, 6.538, 6.451};
  const std::vector<double> later_true = {7.720, 7.339, 7.051, 6.821, 6.599, 3.631,
                                          1.572, 2.419, 7.720, 1.572, 2.419};
  std::vector<double> later;  // along the later pass's own odometry, which lost its scale
  for (const double x : later_true) later.push_back(0.43 * (x - 0.1));
  EXPECT_EQ(ConsistentLoopEdges(earlier, later), (std::vector<int>{0, 1, 2, 3, 4}));
}

TEST(PassConsensus, OppositeSlopesAndSingleEdges) {
  // Two edges whose order is reversed between the passes agree on no forward line.
  EXPECT_TRUE(ConsistentLoopEdges({1.0, 2.0}, {2.0, 1.0}).empty());
  EXPECT_EQ(ConsistentLoopEdges({1.0}, {5.0}), (std::vector<int>{0}));
  EXPECT_TRUE(ConsistentLoopEdges({}, {}).empty());
}

}  // namespace
}  // namespace pipescope
