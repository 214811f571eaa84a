#include "pipescope/image/foreshortening.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "pipescope/camera/camera.h"
#include "pipescope/geometry/camera_mount.h"

namespace pipescope {
namespace {

// Closed form in the cross-section: a camera at y0 = radius - d on the line to the wall, its ray
// at angle a from the optical axis, meets the wall at t = -y0 cos a + sqrt(r^2 - y0^2 sin^2 a),
// at depth t cos a.
double ClosedFormRatio(double radius, double d, double tan_a) {
  const double a = std::atan(tan_a);
  const double y0 = radius - d;
  const double t =
      -y0 * std::cos(a) + std::sqrt(radius * radius - y0 * y0 * std::sin(a) * std::sin(a));
  return d / (t * std::cos(a));
}

TEST(WallDepthRatios, FollowTheCircleForEveryMount) {
  const double radius = 0.0767, focal = 64.0;
  const cv::Point2d principal(63.7, 47.2);
  for (const double d : {radius, 0.05, 0.11}) {  // centred, near the wall, past the axis
    for (const std::string axis : {"x", "-y"}) {
      const bool along_x = axis == "x";
      const int lines = along_x ? 96 : 128;
      const std::vector<double> ratios = WallDepthRatios(
          MountedStartPose({axis}, radius, d), radius, d, focal, principal, lines, along_x);
      ASSERT_EQ(ratios.size(), static_cast<std::size_t>(lines));
      for (int i = 0; i < lines; ++i) {
        const double offset = (i - (along_x ? principal.y : principal.x)) / focal;
        EXPECT_NEAR(ratios[i], ClosedFormRatio(radius, d, offset), 1e-9);
        EXPECT_GE(ratios[i], 1.0 - 1e-12);  // the wall is concave
      }
    }
  }
}

// The property the correction exists for: after the stretch, wall points on every line of the
// band move by the same number of pixels, axial_ratio * zeta * travel, when the camera moves
// along the pipe; without it they do not.
TEST(EqualiseAxialScale, EveryBandLineMovesAtTheSameRate) {
  const double radius = 0.0767, d = 0.07;
  const int width = 256, height = 192;
  const double f = 180.0;
  const cv::Point2d c(127.5, 95.5);
  const Camera camera(CameraModelId::kPinholeRadtan, width, height,
                      {f, f, c.x, c.y, 0.0, 0.0, 0.0, 0.0, 0.0});
  const Eigen::Isometry3d start = MountedStartPose({"x"}, radius, d);
  const std::vector<double> ratios =
      WallDepthRatios(start, radius, d, f, c, height, /*lines_are_rows=*/true);
  const int first = 48, lines = 96;  // the central half
  const AxialScaleEqualisation equalisation = EqualiseAxialScale(ratios, first, lines, true);
  const Undistorter stretched(camera, {.stretch = equalisation.stretch});
  const double zeta = f / d, travel = 0.002;
  double spread_before = 0.0;
  for (int y = first; y < first + lines; y += 5) {
    for (const double x : {40.0, 127.5, 200.0}) {
      // The wall point seen at (x, y), and where it is after the camera travels along +Z.
      Eigen::Vector3d ray((x - c.x) / f, (y - c.y) / f, 1.0);
      const Eigen::Vector3d world_ray = start.linear() * ray;
      double t = 0.0;
      {
        // Ray and circle in the cross-section, as WallDepthRatios does it.
        const Eigen::Vector2d o = start.translation().head<2>(), v = world_ray.head<2>();
        const double a = v.squaredNorm(), b = 2.0 * o.dot(v),
                     cc = o.squaredNorm() - radius * radius;
        t = (-b + std::sqrt(b * b - 4.0 * a * cc)) / (2.0 * a);
      }
      const Eigen::Vector3d point = start.translation() + t * world_ray;
      Eigen::Isometry3d moved = start;
      moved.translation().z() += travel;
      const Eigen::Vector3d in_cam = moved.inverse() * point;
      const double x_after = c.x + f * in_cam.x() / in_cam.z();
      const double y_after = c.y + f * in_cam.y() / in_cam.z();
      EXPECT_NEAR(y_after, y, 1e-9);  // axial travel moves along the rows only
      // In the stretched image a perspective x sits at c.x + (x - c.x) / factor.
      const double factor = equalisation.stretch.factors[y];
      const double shift = ((x_after - c.x) - (x - c.x)) / factor;
      EXPECT_NEAR(std::abs(shift), equalisation.axial_ratio * zeta * travel, 1e-9) << "row " << y;
      spread_before = std::max(spread_before, std::abs(std::abs(x_after - x) - zeta * travel));
      // And the stretched tables sample where the stretch says.
      const cv::Point2f source = stretched.SourcePixel(static_cast<int>(x), y);
      EXPECT_NEAR(source.x, c.x + factor * (static_cast<int>(x) - c.x), 1e-3);
    }
  }
  // Unstretched, the band's edge rows move a few per cent more than the centre's.
  EXPECT_GT(spread_before, 0.01 * zeta * travel);
  for (int i = first; i < first + lines; ++i) EXPECT_LE(equalisation.stretch.factors[i], 1.0);
}

}  // namespace
}  // namespace pipescope
