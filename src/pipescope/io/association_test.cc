#include "pipescope/io/association.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

namespace pipescope {
namespace {

Trajectory FromTimes(const std::vector<double>& times) {
  Trajectory trajectory;
  for (double t : times) {
    StampedPose pose;
    pose.timestamp = t;
    trajectory.push_back(pose);
  }
  return trajectory;
}

std::vector<std::pair<std::size_t, std::size_t>> AsPairs(const std::vector<AssociatedPair>& in) {
  std::vector<std::pair<std::size_t, std::size_t>> out;
  for (const AssociatedPair& pair : in) out.emplace_back(pair.gt_index, pair.est_index);
  return out;
}

using Pairs = std::vector<std::pair<std::size_t, std::size_t>>;

TEST(Association, IdenticalTimesMatchOneToOne) {
  const Trajectory trajectory = FromTimes({0.0, 0.1, 0.2, 0.3});
  EXPECT_EQ(AsPairs(AssociateByTimestamp(trajectory, trajectory)),
            (Pairs{{0, 0}, {1, 1}, {2, 2}, {3, 3}}));
}

TEST(Association, OffsetsWithinAndOutsideTolerance) {
  const Trajectory gt = FromTimes({0.0, 0.1, 0.2, 0.3, 0.4});
  // Offsets 0.005 (in), 0.02 (out), -0.009 (in), 0.011 (out), -0.005 (in).
  const Trajectory est = FromTimes({0.005, 0.12, 0.191, 0.311, 0.395});
  EXPECT_EQ(AsPairs(AssociateByTimestamp(gt, est, 0.01)), (Pairs{{0, 0}, {2, 2}, {4, 4}}));
  // A wider tolerance takes them all.
  EXPECT_EQ(AsPairs(AssociateByTimestamp(gt, est, 0.05)),
            (Pairs{{0, 0}, {1, 1}, {2, 2}, {3, 3}, {4, 4}}));
}

TEST(Association, FasterEstimateKeepsClosestPerGroundTruthPose) {
  // Ground truth at 10 Hz, estimate at 30 Hz offset by 2 ms.
  const Trajectory gt = FromTimes({0.0, 0.1, 0.2});
  std::vector<double> est_times;
  for (int i = 0; i < 9; ++i) est_times.push_back(0.002 + i / 30.0);
  const Trajectory est = FromTimes(est_times);
  // est 0 (0.002), 3 (0.102), 6 (0.202) are 2 ms from a ground-truth pose; the others 31+ ms.
  EXPECT_EQ(AsPairs(AssociateByTimestamp(gt, est, 0.01)), (Pairs{{0, 0}, {1, 3}, {2, 6}}));
  // With a 40 ms tolerance, est 1 and 2 (0.035, 0.069) both have a nearest pose within reach
  // but lose it to a closer estimate: still one-to-one.
  EXPECT_EQ(AsPairs(AssociateByTimestamp(gt, est, 0.04)), (Pairs{{0, 0}, {1, 3}, {2, 6}}));
}

TEST(Association, SlowerEstimateMatchesSubsetOfGroundTruth) {
  std::vector<double> gt_times;
  for (int i = 0; i < 10; ++i) gt_times.push_back(0.1 * i);
  const Trajectory gt = FromTimes(gt_times);
  const Trajectory est = FromTimes({0.301, 0.699, 5.0});  // The last is beyond the ground truth.
  EXPECT_EQ(AsPairs(AssociateByTimestamp(gt, est, 0.01)), (Pairs{{3, 0}, {7, 1}}));
}

TEST(Association, EmptyInputsGiveNoPairsAndUnsortedInputThrows) {
  EXPECT_TRUE(AssociateByTimestamp({}, FromTimes({1.0})).empty());
  EXPECT_TRUE(AssociateByTimestamp(FromTimes({1.0}), {}).empty());
  EXPECT_THROW(AssociateByTimestamp(FromTimes({1.0, 0.5}), FromTimes({1.0})),
               std::invalid_argument);
}

}  // namespace
}  // namespace pipescope
