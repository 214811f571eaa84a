#include "pipescope/pipeline/turn_confirmation.h"

#include <gtest/gtest.h>

namespace pipescope {
namespace {

TIntersectionRecord Turn(int section, const std::string& rejection = "") {
  TIntersectionRecord t;
  t.section = section;
  t.red_keyframe = 10 * section;
  t.blue_keyframe = 10 * section + 5;
  t.rejection = rejection;
  t.modelled = rejection.empty();
  t.model[kPhi] = 97.2 * M_PI / 180.0;
  return t;
}

// Route B's shape: T sections 1, 3, 5, 7, 9 and 11, junction T4 passed at sections 3 and 11, its
// passages `gap_m` apart over 24.5 m of path.
LoopClosureRecord LoopThroughT4(bool applied, double gap_m) {
  LoopClosureRecord record;
  record.applied = applied;
  JunctionRevisit revisit;
  revisit.name = "T4";
  revisit.t_sections = {3, 11};
  revisit.gap_before_m = applied ? 3.1 : gap_m;
  revisit.gap_after_m = gap_m;
  revisit.path_between_m = 24.5;
  record.revisits.push_back(revisit);
  return record;
}

std::vector<TIntersectionRecord> RouteTurns() {
  std::vector<TIntersectionRecord> turns;
  for (int section : {1, 3, 5, 7, 9, 11}) turns.push_back(Turn(section));
  return turns;
}

bool Names(const std::vector<std::string>& reasons, const std::string& what) {
  for (const std::string& reason : reasons) {
    if (reason.find(what) != std::string::npos) return true;
  }
  return false;
}

// Without a loop every turn is unconfirmed, and its reason names it, its angle and what is at
// stake; a T driven straight through is no turn.
TEST(TurnConfirmation, EveryTurnOutsideAClosedLoopIsUnconfirmed) {
  const std::vector<TIntersectionRecord> ts = {Turn(1), Turn(3, "no turn"), Turn(5, "image rms")};
  const std::vector<std::string> reasons =
      UnconfirmedTurnReasons(ts, {"J1", "", "J2"}, LoopClosureRecord());
  ASSERT_EQ(reasons.size(), 2u);
  EXPECT_NE(reasons[0].find("junction J1 (key frames 10-15)"), std::string::npos) << reasons[0];
  EXPECT_NE(reasons[0].find("phi 97.2 deg"), std::string::npos) << reasons[0];
  EXPECT_NE(reasons[0].find("positions past it are not confirmed"), std::string::npos);
  EXPECT_NE(reasons[1].find("chained key frames alone"), std::string::npos) << reasons[1];
  EXPECT_NE(reasons[1].find("image rms"), std::string::npos) << reasons[1];
}

// A junction found again where the run had placed it confirms the turns of the loop between its
// passages (sections 3 to 9), not the last passage's turn out of the loop (11) nor the turn
// before the loop (1). A revisit placed apart confirms nothing, whether or not a closure was
// applied; after a closure, the gap after it counts.
TEST(TurnConfirmation, AHeldLoopConfirmsTheTurnsInsideIt) {
  const std::vector<std::string> names = {"J1", "J2", "J3", "J4", "J5", "J6"};
  for (const bool applied : {false, true}) {
    const std::vector<std::string> held =
        UnconfirmedTurnReasons(RouteTurns(), names, LoopThroughT4(applied, 0.014));
    EXPECT_EQ(held.size(), 2u) << applied;
    EXPECT_TRUE(Names(held, "J1 ")) << applied;
    EXPECT_TRUE(Names(held, "J6 ")) << applied;
    for (const char* inside : {"J2 ", "J3 ", "J4 ", "J5 "}) {
      EXPECT_FALSE(Names(held, inside)) << inside << " " << applied;
    }
    // 0.3 m over 24.5 m of path is more than 1 %.
    EXPECT_EQ(UnconfirmedTurnReasons(RouteTurns(), names, LoopThroughT4(applied, 0.3)).size(), 6u)
        << applied;
  }
}

// A T held at a given fitting angle: as a record with phi_given, its phi the held angle and
// initial_model the end cylinders' own.
TIntersectionRecord HeldTurn(int section, double held_deg, double own_deg) {
  TIntersectionRecord t = Turn(section);
  t.phi_given = true;
  t.model[kPhi] = held_deg * M_PI / 180.0;
  t.initial_model[kPhi] = own_deg * M_PI / 180.0;
  return t;
}

// A given fitting angle does not confirm a turn (nothing but a held loop does), but its reason
// says the angle was given and whether the end cylinders meet within 20 degrees of it; one
// beyond names both angles.
TEST(TurnConfirmation, AGivenFittingAngleIsNamedAndCheckedButConfirmsNothing) {
  const std::vector<TIntersectionRecord> ts = {
      HeldTurn(1, 90.0, 103.3), HeldTurn(3, 90.0, 76.0),
      HeldTurn(5, 90.0, 47.0),    // a wye taken for a tee
      HeldTurn(7, 135.0, 133.0),  // a 45-degree wye, its branch taken the other way
      Turn(9, "image rms")};
  const std::vector<std::string> reasons =
      UnconfirmedTurnReasons(ts, {"J1", "J2", "J3", "J4", ""}, LoopClosureRecord());
  ASSERT_EQ(reasons.size(), 5u);
  for (int i = 0; i < 4; ++i) {
    EXPECT_NE(reasons[i].find("held at the given fitting angle"), std::string::npos) << reasons[i];
    EXPECT_NE(reasons[i].find("positions past it are not confirmed"), std::string::npos);
  }
  EXPECT_NE(reasons[0].find("(90.0 deg"), std::string::npos) << reasons[0];
  EXPECT_NE(reasons[3].find("(135.0 deg"), std::string::npos) << reasons[3];
  for (int i : {0, 1, 3}) {
    EXPECT_EQ(reasons[i].find("may not be what was given"), std::string::npos) << reasons[i];
  }
  EXPECT_NE(reasons[2].find("meet at 47.0 deg, more than 20 deg from it"), std::string::npos)
      << reasons[2];
  EXPECT_NE(reasons[4].find("chained key frames alone"), std::string::npos) << reasons[4];
  // Inside a held loop a held turn is confirmed like any other.
  EXPECT_TRUE(UnconfirmedTurnReasons({HeldTurn(5, 90.0, 92.0)}, {"J3"}, LoopThroughT4(true, 0.014))
                  .empty());
}

}  // namespace
}  // namespace pipescope
