#include "pipescope/estimation/loop_candidates.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <string>
#include <vector>

#include "pipescope/util/error.h"

namespace pipescope {
namespace {

using Eigen::Vector3d;

const Vector3d kUp = Vector3d::UnitZ();
constexpr double kSideM = 8.15;  // 001 Table I: the T centres are about 8.15 m apart

// 001 Fig. 5 in the X-Y plane: T1..T4 (junctions 0..3) round a square, T1 -> T2 -> T3 -> T4
// turning left. Sections 0..3 are the sides, side j from junction j (its end 0) to junction j + 1
// (its end 1); sections 4..7 are the dead-end arms, arm 4 + j running on from junction j (its
// end 0) in the direction of the side that arrives there, as the simulator's square loop has it.
const Vector3d kJunctions[4] = {{0, 0, 0}, {0, kSideM, 0}, {-kSideM, kSideM, 0}, {-kSideM, 0, 0}};
constexpr int kArm = 4;

PipeNetwork SquareLoopNetwork() {
  PipeNetwork network;
  network.section_ends.resize(8);
  for (int j = 0; j < 4; ++j) {
    const int arriving = (j + 3) % 4, leaving = j, arm = kArm + j;
    SectionEndExits& from_arriving = network.section_ends[arriving][1];
    from_arriving.straight = {arm, 0};
    from_arriving.left = {leaving, 0};
    SectionEndExits& from_arm = network.section_ends[arm][0];
    from_arm.straight = {arriving, 1};
    from_arm.right = {leaving, 0};
    SectionEndExits& from_leaving = network.section_ends[leaving][0];
    from_leaving.left = {arm, 0};
    from_leaving.right = {arriving, 1};
  }
  return network;
}

// The turns of a route through `waypoints` (start, the junction centres in order, end).
std::vector<int> TurnsThrough(const std::vector<Vector3d>& waypoints) {
  std::vector<int> turns;
  for (size_t k = 1; k + 1 < waypoints.size(); ++k) {
    turns.push_back(
        TurnDirection(waypoints[k] - waypoints[k - 1], waypoints[k + 1] - waypoints[k], kUp));
  }
  return turns;
}

// A run's key frames as its odometry has them: each pass drifted by its own rigid motion, the
// junction centroids with it.
struct SyntheticRun {
  std::vector<Vector3d> positions;
  std::vector<int> pass_of_key_frame;
  std::vector<double> true_distance_to_pass_end;  // along the pipe, of each key frame
  std::vector<PassJunctions> passes;
};

// Pass p drives from waypoints[p] to waypoints[p + 1]; its key frames start `skip_start_m` in and
// stop `skip_end_m` short (the frames in the junctions are not straight), every `spacing_m` from
// an `offset_m`, weaving 1 cm across the pipe. The first waypoint and, unless `ends_at_junction`,
// the last are dead ends.
struct PassSampling {
  double skip_start_m = 0.5, skip_end_m = 0.5, spacing_m = 0.010, offset_m = 0.0;
};

SyntheticRun DriveRoute(const std::vector<Vector3d>& waypoints,
                        const std::vector<SectionPass>& named, bool ends_at_junction,
                        const std::vector<PassSampling>& sampling) {
  SyntheticRun run;
  const int pass_count = static_cast<int>(waypoints.size()) - 1;
  for (int p = 0; p < pass_count; ++p) {
    const Eigen::Isometry3d drift =
        Eigen::Translation3d(0.05 * p, -0.03 * p, 0.01 * p) * Eigen::AngleAxisd(0.01 * p, kUp);
    const Vector3d start = waypoints[p], end = waypoints[p + 1];
    const Vector3d axis = (end - start).normalized();
    const Vector3d across = kUp.cross(axis);
    const double length = (end - start).norm();
    const PassSampling& s = sampling[p];
    run.positions.push_back(drift * start);  // a key frame inside the junction: in no pass
    run.pass_of_key_frame.push_back(-1);
    run.true_distance_to_pass_end.push_back(length);
    for (double along = s.skip_start_m + s.offset_m; along <= length - s.skip_end_m;
         along += s.spacing_m) {
      const Vector3d truth = start + along * axis + 0.01 * std::sin(3.0 * along) * across;
      run.positions.push_back(drift * truth);
      run.pass_of_key_frame.push_back(p);
      run.true_distance_to_pass_end.push_back(length - along);
    }
    PassJunctions pass;
    pass.pass = named[p];
    if (p > 0) pass.start_centroid = drift * start;
    if (p + 1 < pass_count || ends_at_junction) pass.end_centroid = drift * end;
    run.passes.push_back(pass);
  }
  return run;
}

bool operator==(const SectionPass& a, const SectionPass& b) {
  return a.section == b.section && a.toward_end == b.toward_end;
}

TEST(TurnDirection, LeftRightAndStraightSeenFromUp) {
  const Vector3d east = Vector3d::UnitX(), north = Vector3d::UnitY();
  EXPECT_EQ(TurnDirection(east, north, kUp), 1);
  EXPECT_EQ(TurnDirection(east, -north, kUp), -1);
  EXPECT_EQ(TurnDirection(east, north, -kUp), -1);            // seen from below, left is right
  EXPECT_EQ(TurnDirection(3.0 * east, 0.2 * north, kUp), 1);  // lengths do not matter
}

TEST(TurnDirection, StraightThroughAJunctionIsNoTurn) {
  const Vector3d east = Vector3d::UnitX();
  const Vector3d ten_degrees_left = Eigen::AngleAxisd(10.0 * M_PI / 180.0, kUp) * east;
  const Vector3d fifty_degrees_right = Eigen::AngleAxisd(-50.0 * M_PI / 180.0, kUp) * east;
  EXPECT_EQ(TurnDirection(east, east, kUp), 0);
  EXPECT_EQ(TurnDirection(east, ten_degrees_left, kUp), 0);
  EXPECT_EQ(TurnDirection(east, fifty_degrees_right, kUp), -1);
  EXPECT_EQ(TurnDirection(east, fifty_degrees_right, kUp, 60.0 * M_PI / 180.0), 0);
  EXPECT_THROW(TurnDirection(Vector3d::Zero(), east, kUp), InputError);
}

// 001 dataset B, as the simulator drives it: from T1's arm straight through T1 to T4, round the
// loop T4-T3-T2-T1 turning right, along T1-T4 a second time and left at T4 into its arm.
TEST(SelectLoopCandidates, RouteBClosesOnlyTheSectionDrivenTwice) {
  const Vector3d t1 = kJunctions[0], t2 = kJunctions[1], t3 = kJunctions[2], t4 = kJunctions[3];
  const std::vector<Vector3d> waypoints = {t1 + 3.0 * Vector3d::UnitX(), t1, t4, t3, t2, t1, t4,
                                           t4 - 3.0 * Vector3d::UnitY()};
  const std::vector<int> turns = TurnsThrough(waypoints);
  EXPECT_EQ(turns, (std::vector<int>{0, -1, -1, -1, -1, 1}));

  const std::vector<SectionPass> named = NameSectionPasses(SquareLoopNetwork(), {kArm, 0}, turns);
  // Arm of T1, T1-T4 (side 3, towards its end 0 at T4), T4-T3, T3-T2, T2-T1, T1-T4, arm of T4.
  const std::vector<SectionPass> expected = {{kArm, 0}, {3, 0}, {2, 0},       {1, 0},
                                             {0, 0},    {3, 0}, {kArm + 3, 1}};
  ASSERT_EQ(named.size(), expected.size());
  for (size_t p = 0; p < expected.size(); ++p) EXPECT_TRUE(named[p] == expected[p]) << p;

  // The second pass along T1-T4 has coarser key frames, offset by 3 mm, over a shorter stretch.
  std::vector<PassSampling> sampling(named.size());
  sampling[5] = {1.0, 0.8, 0.007, 0.003};
  const SyntheticRun run = DriveRoute(waypoints, named, false, sampling);
  const std::vector<LoopCandidate> candidates =
      SelectLoopCandidates(run.positions, run.pass_of_key_frame, run.passes);

  ASSERT_EQ(candidates.size(), 15u);
  const double low = 0.8, high = kSideM - 1.0;  // the stretch both passes cover, from T4
  const double step = (high - low) / 15.0;
  for (size_t c = 0; c < candidates.size(); ++c) {
    const LoopCandidate& pair = candidates[c];
    EXPECT_EQ(run.pass_of_key_frame[pair.earlier], 1) << c;
    EXPECT_EQ(run.pass_of_key_frame[pair.later], 5) << c;
    EXPECT_NEAR(pair.earlier_distance_m,
                (run.positions[pair.earlier] - *run.passes[1].end_centroid).norm(), 1e-12);
    EXPECT_NEAR(pair.later_distance_m,
                (run.positions[pair.later] - *run.passes[5].end_centroid).norm(), 1e-12);
    EXPECT_LE(std::abs(pair.earlier_distance_m - pair.later_distance_m), 0.005) << c;
    // Truly the same place along the pipe: nearest key frames 3.5 mm apart at most, plus the
    // weave's share of the Euclidean distance.
    EXPECT_LE(std::abs(run.true_distance_to_pass_end[pair.earlier] -
                       run.true_distance_to_pass_end[pair.later]),
              0.006)
        << c;
    if (c > 0) {
      const double gap = pair.earlier_distance_m - candidates[c - 1].earlier_distance_m;
      EXPECT_GT(gap, 0.5 * step) << c;
      EXPECT_LT(gap, 1.5 * step) << c;
    }
  }
  EXPECT_LT(candidates.front().earlier_distance_m, low + step);
  EXPECT_GT(candidates.back().earlier_distance_m, high - step);
}

// 001 dataset A: start-T1-T2-T3-T4-end, ending 1 m before T1; no section is driven twice.
TEST(SelectLoopCandidates, RouteWithoutARepeatedSectionHasNone) {
  const Vector3d t1 = kJunctions[0], t2 = kJunctions[1], t3 = kJunctions[2], t4 = kJunctions[3];
  const std::vector<Vector3d> waypoints = {t1 + 3.0 * Vector3d::UnitX(), t1, t2, t3, t4,
                                           t1 - 1.0 * Vector3d::UnitX()};
  const std::vector<int> turns = TurnsThrough(waypoints);
  EXPECT_EQ(turns, (std::vector<int>{-1, 1, 1, 1}));
  const std::vector<SectionPass> named = NameSectionPasses(SquareLoopNetwork(), {kArm, 0}, turns);
  const std::vector<SectionPass> expected = {{kArm, 0}, {0, 1}, {1, 1}, {2, 1}, {3, 1}};
  ASSERT_EQ(named.size(), expected.size());
  for (size_t p = 0; p < expected.size(); ++p) EXPECT_TRUE(named[p] == expected[p]) << p;

  const SyntheticRun run =
      DriveRoute(waypoints, named, false, std::vector<PassSampling>(named.size()));
  EXPECT_TRUE(SelectLoopCandidates(run.positions, run.pass_of_key_frame, run.passes).empty());
}

// Two passes of one section in opposite directions share the junction one ends at and the
// other starts from; without it they share none and give no pairs. Where the later pass has a
// gap, the earlier one's key frames find no match within the tolerance.
TEST(SelectLoopCandidates, OppositePassesMeasureFromTheJunctionBothKnow) {
  std::vector<Vector3d> positions;
  std::vector<int> pass_of_key_frame;
  const Vector3d junction(0.0, 0.0, 0.0), shifted(0.2, 0.1, 0.0);  // the second pass drifted
  for (double d = 0.5; d <= 3.0; d += 0.01) {  // towards the junction at the section's end 1
    positions.push_back(junction - d * Vector3d::UnitX());
    pass_of_key_frame.push_back(0);
  }
  for (double d = 0.504; d <= 3.0; d += 0.01) {  // away from it, no key frames in [1.5, 2] m
    if (d > 1.5 && d < 2.0) continue;
    positions.push_back(shifted - d * Vector3d::UnitX());
    pass_of_key_frame.push_back(1);
  }
  std::vector<PassJunctions> passes(2);
  passes[0].pass = {0, 1};
  passes[0].end_centroid = junction;
  passes[1].pass = {0, 0};
  passes[1].start_centroid = shifted;

  LoopCandidateOptions options;
  options.max_pairs = 5;
  const std::vector<LoopCandidate> candidates =
      SelectLoopCandidates(positions, pass_of_key_frame, passes, options);
  ASSERT_EQ(candidates.size(), 5u);
  for (const LoopCandidate& pair : candidates) {
    EXPECT_NEAR(pair.earlier_distance_m, pair.later_distance_m, 0.005);
    EXPECT_EQ(pass_of_key_frame[pair.later], 1);
    // The later pass has nothing to match there within the tolerance.
    EXPECT_FALSE(pair.earlier_distance_m > 1.51 && pair.earlier_distance_m < 1.99)
        << pair.earlier_distance_m;
  }

  passes[1].start_centroid.reset();
  EXPECT_TRUE(SelectLoopCandidates(positions, pass_of_key_frame, passes, options).empty());
}

TEST(SelectLoopCandidates, InvalidInputIsRejected) {
  const std::vector<PassJunctions> passes(2);
  EXPECT_THROW(SelectLoopCandidates({Vector3d::Zero()}, {0, 1}, passes), InputError);
  EXPECT_THROW(SelectLoopCandidates({Vector3d::Zero()}, {2}, passes), InputError);
}

TEST(NameSectionPasses, ATurnIntoNoPipeIsNamed) {
  // Left at T2 onto T2-T3; arriving at T3 along it there is no pipe to the right.
  try {
    NameSectionPasses(SquareLoopNetwork(), {0, 1}, {1, -1});
    FAIL() << "no InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("turn 1 (right) at end 1 of section 1"),
              std::string::npos)
        << error.what();
  }
  EXPECT_THROW(NameSectionPasses(SquareLoopNetwork(), {8, 0}, {}), InputError);
}

}  // namespace
}  // namespace pipescope
