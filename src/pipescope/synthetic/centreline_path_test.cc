#include "pipescope/synthetic/centreline_path.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace pipescope {
namespace {

TEST(CentrelinePath, RoundedCornerHasClosedFormLengthAndGeometry) {
  const double radius = 0.5;
  const CentrelinePath path({{0, 0, 0}, {0, 0, 2}, {3, 0, 2}}, radius);
  // Two legs of 2 and 3 m, each shortened by R tan(45 deg), plus a quarter circle.
  EXPECT_NEAR(path.Length(), 2.0 + 3.0 - 2.0 * radius + radius * M_PI / 2.0, 1e-12);
  ASSERT_EQ(path.pieces().size(), 3u);
  const CentrelinePath::Piece& arc = path.pieces()[1];
  EXPECT_TRUE(arc.is_arc);
  EXPECT_TRUE(arc.center.isApprox(Eigen::Vector3d(0.5, 0, 1.5), 1e-12));
  Eigen::Vector3d point, tangent;
  for (double s = arc.start_s; s <= arc.start_s + arc.length; s += 0.01) {
    path.Evaluate(s, &point, &tangent);
    EXPECT_NEAR((point - arc.center).norm(), radius, 1e-12);
    EXPECT_NEAR(tangent.dot(point - arc.center), 0.0, 1e-12);
  }
  path.Evaluate(path.Length(), &point, &tangent);
  EXPECT_TRUE(point.isApprox(Eigen::Vector3d(3, 0, 2), 1e-12));
  EXPECT_TRUE(tangent.isApprox(Eigen::Vector3d(1, 0, 0), 1e-12));
}

TEST(CentrelinePath, IsContinuousWithContinuousTangent) {
  const CentrelinePath path({{0, 0, 0}, {0, 0, 2}, {2, 0, 3}, {2, 0, 6}}, 0.3);
  Eigen::Vector3d previous_point, previous_tangent, point, tangent;
  path.Evaluate(0.0, &previous_point, &previous_tangent);
  const double step = 1e-3;
  for (double s = step; s <= path.Length(); s += step) {
    path.Evaluate(s, &point, &tangent);
    EXPECT_NEAR((point - previous_point).norm(), step, 1e-6);
    EXPECT_LT((tangent - previous_tangent).norm(), 0.01);
    previous_point = point;
    previous_tangent = tangent;
  }
}

TEST(CentrelinePath, RejectsLegsTooShortForTheCorner) {
  EXPECT_THROW(CentrelinePath({{0, 0, 0}, {0, 0, 0.1}, {1, 0, 0.1}}, 0.5), std::invalid_argument);
}

}  // namespace
}  // namespace pipescope
