#include "pipescope/pipeline/loop_closure_pass.h"

#include <gtest/gtest.h>

namespace pipescope {
namespace {

LoopClosureRecord WithRevisit(bool applied, double gap_before_m, double gap_after_m) {
  LoopClosureRecord record;
  record.applied = applied;
  JunctionRevisit revisit;
  revisit.name = "T4";
  revisit.t_sections = {3, 11};
  revisit.gap_before_m = gap_before_m;
  revisit.gap_after_m = gap_after_m;
  revisit.path_between_m = 24.5;
  record.revisits.push_back(revisit);
  return record;
}

// A junction placed twice, 9.4 m apart after 24.5 m of path, is a map that disagrees with
// itself: the run is unreliable, and the reason names the junction. Within 1 % of the path it is
// not; after a closure, the gap after it counts.
TEST(LoopClosurePass, ARevisitedJunctionPlacedApartMakesTheRunUnreliable) {
  const std::vector<std::string> reasons = RevisitReasons(WithRevisit(false, 9.4, 9.4));
  ASSERT_EQ(reasons.size(), 1u);
  EXPECT_NE(reasons[0].find("T4"), std::string::npos) << reasons[0];
  EXPECT_NE(reasons[0].find("no loop closure"), std::string::npos) << reasons[0];
  EXPECT_TRUE(RevisitReasons(WithRevisit(false, 0.2, 0.2)).empty());
  EXPECT_TRUE(RevisitReasons(WithRevisit(true, 9.4, 0.2)).empty());
  EXPECT_EQ(RevisitReasons(WithRevisit(true, 0.2, 0.3)).size(), 1u);
}

}  // namespace
}  // namespace pipescope
