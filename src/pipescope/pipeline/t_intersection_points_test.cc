#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <map>

#include "pipescope/pipeline/t_intersection_pass.h"

namespace pipescope {
namespace {

// Points of the red section (1), the T (2) and the blue section (3); tracks 10 and 11 are the red
// section's last stretch, seen again inside the T and re-triangulated there.
std::vector<SparsePoint> MapPoints() {
  return {{{0.0, 0.1, 1.0}, 1, 9},  {{0.0, 0.1, 1.9}, 1, 10}, {{0.1, 0.0, 2.0}, 1, 11},
          {{0.2, 0.0, 2.5}, 2, 20}, {{0.0, 0.2, 3.0}, 3, 30}, {{0.0, 0.0, 0.5}, 1, -1}};
}

TIntersectionRecord AdjustedT() {
  TIntersectionRecord t;
  t.correction =
      Eigen::Translation3d(0.0, 0.0, 0.05) * Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitY());
  t.points = {{0.0, 0.1, 1.91}, {0.1, 0.0, 2.02}, {0.2, 0.01, 2.52}, {0.3, 0.0, 2.6}};
  t.point_tracks = {10, 11, 20, 21};
  return t;
}

TEST(MergeTIntersectionPoints, EachTrackIsInTheMapOnceWithTheTsPosition) {
  const TIntersectionRecord t = AdjustedT();
  const std::vector<SparsePoint> merged = MergeTIntersectionPoints(MapPoints(), 2, t);
  std::map<long, std::vector<SparsePoint>> by_track;
  for (const SparsePoint& point : merged) by_track[point.track_id].push_back(point);
  for (const auto& [track, copies] : by_track) EXPECT_EQ(copies.size(), 1u) << "track " << track;
  // The T's points replace the red tail's (tracks 10 and 11) and the T's own (20), in the T.
  for (std::size_t p = 0; p < t.points.size(); ++p) {
    const SparsePoint& point = by_track.at(t.point_tracks[p]).front();
    EXPECT_EQ(point.section, 2);
    EXPECT_TRUE(point.position.isApprox(t.points[p]));
  }
  // The red section's other points stay; the blue section's follow the correction.
  EXPECT_TRUE(by_track.at(9).front().position.isApprox(Eigen::Vector3d(0.0, 0.1, 1.0)));
  EXPECT_TRUE(by_track.at(-1).front().position.isApprox(Eigen::Vector3d(0.0, 0.0, 0.5)));
  EXPECT_TRUE(
      by_track.at(30).front().position.isApprox(t.correction * Eigen::Vector3d(0.0, 0.2, 3.0)));
  EXPECT_EQ(merged.size(), 7u);  // 9, -1, 30 and the T's four
}

TEST(MergeTIntersectionPoints, PointsWithoutATrackAreKept) {
  TIntersectionRecord t = AdjustedT();
  t.point_tracks.clear();  // e.g. an older record: the T's points are added, nothing else goes
  const std::vector<SparsePoint> merged = MergeTIntersectionPoints(MapPoints(), 2, t);
  EXPECT_EQ(merged.size(), 5u + t.points.size());  // all but the T section's one
}

}  // namespace
}  // namespace pipescope
