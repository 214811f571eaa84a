// The unrolling maps are checked against closed forms (pinhole, OpenCV's fisheye projection),
// and unrolled simulator frames against each other and against the simulator's wall texture.
#include "pipescope/image/wall_unrolling.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/calib3d.hpp>
#include <vector>

#include "pipescope/image/unrolling_testing.h"

namespace pipescope {
namespace {

// A wall-looking camera (000 Fig. 3): image x along the pipe (world Z), optical axis towards
// the wall at phi = 90 degrees (world +Y), image y along world X.
Eigen::Isometry3d WallLookingPose(const Eigen::Vector3d& position) {
  Eigen::Isometry3d world_from_cam = Eigen::Isometry3d::Identity();
  Eigen::Matrix3d rotation;
  rotation.col(0) = Eigen::Vector3d::UnitZ();
  rotation.col(1) = Eigen::Vector3d::UnitX();
  rotation.col(2) = Eigen::Vector3d::UnitY();
  world_from_cam.linear() = rotation;
  world_from_cam.translation() = position;
  return world_from_cam;
}

TEST(UnrolledGrid, WallPointFollowsThePipeFrame) {
  const UnrolledGrid grid{0.2, 1.0, 0.1, 0.001, cv::Size(10, 10)};
  const Eigen::Vector3d point = grid.WallPoint(3.0, 4.5);
  const double phi = (0.1 + 4.5 * 0.001) / 0.2;
  EXPECT_NEAR(point.x(), 0.2 * std::cos(phi), 1e-12);
  EXPECT_NEAR(point.y(), 0.2 * std::sin(phi), 1e-12);
  EXPECT_NEAR(point.z(), 1.003, 1e-12);
  // s = r pi / 2 is the +Y wall, as the simulator's s_m for a pipe along +Z with reference +X.
  const UnrolledGrid quarter{0.2, 0.0, 0.2 * M_PI / 2, 0.001, cv::Size(1, 1)};
  EXPECT_NEAR((quarter.WallPoint(0, 0) - Eigen::Vector3d(0, 0.2, 0)).norm(), 0.0, 1e-12);
}

TEST(BuildUnrollingMaps, PinholeMatchesClosedForm) {
  const double f = 500.0, cx = 319.5, cy = 239.5;
  const Camera camera(CameraModelId::kPinholeRadtan, 640, 480, {f, f, cx, cy, 0, 0, 0, 0, 0});
  const Eigen::Isometry3d world_from_cam = WallLookingPose({0.01, -0.02, 0.3});
  const double radius = 0.2;
  // The whole circumference around h = 0.3: the far half of the pipe lies behind the camera.
  UnrolledGrid grid{radius, 0.2, 0.0, 0.002, cv::Size(100, 0)};
  grid.size.height = static_cast<int>(2 * M_PI * radius / grid.pixel_m);
  cv::Mat map_x, map_y;
  BuildUnrollingMaps(camera, world_from_cam, grid, &map_x, &map_y);
  ASSERT_EQ(map_x.size(), grid.size);
  const Eigen::Isometry3d cam_from_world = world_from_cam.inverse();
  int valid = 0, invalid = 0;
  for (int v = 0; v < grid.size.height; ++v) {
    for (int u = 0; u < grid.size.width; ++u) {
      const double phi = v * grid.pixel_m / radius;
      const Eigen::Vector3d point_world(radius * std::cos(phi), radius * std::sin(phi),
                                        0.2 + u * grid.pixel_m);
      const Eigen::Vector3d p = cam_from_world * point_world;
      const double x = f * p.x() / p.z() + cx;
      const double y = f * p.y() / p.z() + cy;
      const bool visible = p.z() > 0 && x >= -0.5 && x <= 639.5 && y >= -0.5 && y <= 479.5;
      if (visible) {
        ++valid;
        ASSERT_NEAR(map_x.at<float>(v, u), x, 1e-3) << u << " " << v;
        ASSERT_NEAR(map_y.at<float>(v, u), y, 1e-3) << u << " " << v;
      } else {
        ++invalid;
        ASSERT_EQ(map_x.at<float>(v, u), -1.0f) << u << " " << v;
        ASSERT_EQ(map_y.at<float>(v, u), -1.0f) << u << " " << v;
      }
    }
  }
  EXPECT_GT(valid, 1000);
  EXPECT_GT(invalid, 1000);
}

TEST(BuildUnrollingMaps, KannalaBrandtMatchesOpenCvFisheye) {
  const std::vector<double> params = {300, 310, 330.2, 241.7, 0.02, -0.01, 0.003, -0.001};
  const Camera camera(CameraModelId::kKannalaBrandt, 640, 480, params);
  const Eigen::Isometry3d world_from_cam = WallLookingPose({-0.03, 0.05, 1.0});
  const UnrolledGrid grid{0.15, 0.8, 0.05, 0.004, cv::Size(100, 60)};
  cv::Mat map_x, map_y;
  BuildUnrollingMaps(camera, world_from_cam, grid, &map_x, &map_y);

  const Eigen::Isometry3d cam_from_world = world_from_cam.inverse();
  std::vector<cv::Point3d> points;
  std::vector<cv::Point> cells;
  for (int v = 0; v < grid.size.height; v += 3) {
    for (int u = 0; u < grid.size.width; u += 3) {
      const Eigen::Vector3d p = cam_from_world * grid.WallPoint(u, v);
      if (p.z() <= 0.05) continue;  // OpenCV's fisheye projects points behind the camera too
      points.emplace_back(p.x(), p.y(), p.z());
      cells.emplace_back(u, v);
    }
  }
  ASSERT_GT(points.size(), 200u);
  const cv::Matx33d k(params[0], 0, params[2], 0, params[1], params[3], 0, 0, 1);
  const cv::Vec4d d(params[4], params[5], params[6], params[7]);
  std::vector<cv::Point2d> pixels;
  cv::fisheye::projectPoints(points, pixels, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), k, d);
  int compared = 0;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const cv::Point2d& pixel = pixels[i];
    const float x = map_x.at<float>(cells[i]);
    const float y = map_y.at<float>(cells[i]);
    const bool inside = pixel.x >= -0.5 && pixel.x <= 639.5 && pixel.y >= -0.5 && pixel.y <= 479.5;
    // Only cells clear of the image border, where rounding cannot flip the decision.
    const bool clear = pixel.x > 0 && pixel.x < 639 && pixel.y > 0 && pixel.y < 479;
    if (inside && clear) {
      ++compared;
      EXPECT_NEAR(x, pixel.x, 2e-3);
      EXPECT_NEAR(y, pixel.y, 2e-3);
    } else if (!inside) {
      EXPECT_EQ(x, -1.0f);
    }
  }
  EXPECT_GT(compared, 100);
}

// The lattice maps against every cell projected on its own, for the steel-6in camera (1024x768,
// 70 degrees, radial distortion) at its own ground resolution, off the axis and tilted as the
// robot wobbles, so the footprint crosses the image's edges at odd angles.
class LatticeMaps : public testing::TestWithParam<int> {};

TEST_P(LatticeMaps, MatchTheExactMaps) {
  const Camera camera(CameraModelId::kPinholeRadtan, 1024, 768,
                      {731.21, 731.21, 511.5, 383.5, -0.0654, 0, 0, 0, 0});
  const double radius = 0.07666;
  Eigen::Isometry3d world_from_cam = WallLookingPose({0.004, -0.003, 0.5});
  world_from_cam.linear() =
      Eigen::AngleAxisd(0.02, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix() *
      world_from_cam.linear();
  const double pixel = 1.0 / 9538.37;
  // The band around the +Y wall, wider than the view (0.14 m of 0.48 m around), and 0.13 m
  // along the pipe: 1365 x 1240 cells, a few more than the frame has pixels.
  const UnrolledGrid grid{radius, 0.435, radius * M_PI / 2 - 0.065, pixel, cv::Size(1240, 1365)};
  cv::Mat exact_x, exact_y, lattice_x, lattice_y;
  BuildUnrollingMaps(camera, world_from_cam, grid, &exact_x, &exact_y, 1);
  BuildUnrollingMaps(camera, world_from_cam, grid, &lattice_x, &lattice_y, GetParam());
  ASSERT_EQ(lattice_x.size(), grid.size);
  int seen = 0, disagree = 0;
  double largest = 0.0;
  for (int v = 0; v < grid.size.height; ++v) {
    for (int u = 0; u < grid.size.width; ++u) {
      const bool seen_exact = exact_x.at<float>(v, u) != -1.0f;
      const bool seen_lattice = lattice_x.at<float>(v, u) != -1.0f;
      if (seen_exact != seen_lattice) {
        ++disagree;
        continue;
      }
      if (!seen_exact) {
        ASSERT_EQ(lattice_y.at<float>(v, u), -1.0f);
        continue;
      }
      ++seen;
      const double dx = lattice_x.at<float>(v, u) - exact_x.at<float>(v, u);
      const double dy = lattice_y.at<float>(v, u) - exact_y.at<float>(v, u);
      largest = std::max({largest, std::abs(dx), std::abs(dy)});
    }
  }
  std::printf("lattice %d: %d cells seen, %d disagree on being seen, largest difference %.5f px\n",
              GetParam(), seen, disagree, largest);
  EXPECT_GT(seen, 700000);
  // Only where the interpolation moves a cell across the image's edge.
  EXPECT_LT(disagree, 20);
  // The interpolation error grows as the step squared (measured: 0.0007 and 0.0028 px at 2 and
  // 4 cells, 0.011 px at 8 before blocks wider than 6 px were projected cell by cell; now 0).
  const double step = GetParam();
  EXPECT_LT(largest, 0.001 * step * step);
}

INSTANTIATE_TEST_SUITE_P(Steps, LatticeMaps, testing::Values(2, 4, 8));

// Cells of 5 image pixels (a coarse mosaic): a block of 4 would span 20 px and bend by about
// half a pixel, so the blocks are projected cell by cell and the maps stay exact.
TEST(LatticeMaps, CoarseCellsAreProjectedExactly) {
  const Camera camera(CameraModelId::kPinholeRadtan, 1024, 768,
                      {731.21, 731.21, 511.5, 383.5, -0.0654, 0, 0, 0, 0});
  const double radius = 0.07666;
  const Eigen::Isometry3d world_from_cam = WallLookingPose({0.004, -0.003, 0.5});
  const double pixel = 5.0 / 9538.37;
  const UnrolledGrid grid{radius, 0.435, radius * M_PI / 2 - 0.065, pixel, cv::Size(248, 273)};
  cv::Mat exact_x, exact_y, lattice_x, lattice_y;
  BuildUnrollingMaps(camera, world_from_cam, grid, &exact_x, &exact_y, 1);
  BuildUnrollingMaps(camera, world_from_cam, grid, &lattice_x, &lattice_y, 4);
  EXPECT_GT(cv::countNonZero(exact_x != -1.0f), 25000);
  EXPECT_LT(cv::norm(lattice_x, exact_x, cv::NORM_INF), 1e-4);
  EXPECT_LT(cv::norm(lattice_y, exact_y, cv::NORM_INF), 1e-4);
}

TEST(UnrollFrame, BilinearIsExactOnARampAndMasksTheBorder) {
  cv::Mat frame(40, 50, CV_32F);
  for (int y = 0; y < frame.rows; ++y) {
    for (int x = 0; x < frame.cols; ++x) frame.at<float>(y, x) = 2.0f * x - 3.0f * y + 7.0f;
  }
  frame.at<float>(30, 10) = NAN;
  const std::vector<cv::Point2f> samples = {
      {3.25f, 4.5f},  {0.0f, 0.0f},  {49.0f, 39.0f}, {48.5f, 38.75f},  // inside
      {-0.1f, 5.0f},  {5.0f, -0.2f}, {49.2f, 3.0f},  {3.0f, 39.1f},    // past the taps
      {-1.0f, -1.0f},                                                  // invalid cell
      {10.5f, 29.5f}, {9.5f, 30.5f},                                   // taps the NaN
      {12.0f, 30.0f}};                                                 // next to it
  cv::Mat map_x(1, samples.size(), CV_32F), map_y(1, samples.size(), CV_32F);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    map_x.at<float>(0, i) = samples[i].x;
    map_y.at<float>(0, i) = samples[i].y;
  }
  cv::Mat valid;
  const cv::Mat values = UnrollFrame(frame, map_x, map_y, &valid);
  const std::vector<bool> expected_valid = {true,  true,  true,  true,  false, false,
                                            false, false, false, false, false, true};
  for (std::size_t i = 0; i < samples.size(); ++i) {
    EXPECT_EQ(valid.at<uchar>(0, i) == 255, expected_valid[i]) << i;
    if (expected_valid[i]) {
      EXPECT_NEAR(values.at<float>(0, i), 2.0f * samples[i].x - 3.0f * samples[i].y + 7.0f, 1e-4)
          << i;
    } else {
      EXPECT_EQ(values.at<float>(0, i), 0.0f) << i;
    }
  }
}

// Unrolling simulator frames at their true poses: each wall cell gets the same texture from
// every frame that sees it, and that texture is the simulator's own.
class UnrollSimulatedFrames : public testing::Test {
 protected:
  UnrollSimulatedFrames() : simulation_(SmallSteelConfig()), frames_(simulation_) {}

  // A grid around the wall point frame `index` looks at, at about the image's own resolution.
  UnrolledGrid GridAround(int index) const {
    const double radius = simulation_.config().radius_m;
    const double pixel = 1.0 / 3700.0;  // 1 / zeta of this camera (~3725 px/m)
    const cv::Size size(256, 192);
    const double h = simulation_.FramePose(index).translation().z();
    return {radius, h - 0.5 * size.width * pixel, radius * M_PI / 2 - 0.5 * size.height * pixel,
            pixel, size};
  }

  cv::Mat Unroll(int index, const UnrolledGrid& grid, const Eigen::Isometry3d& world_from_cam,
                 cv::Mat* valid) const {
    cv::Mat map_x, map_y;
    BuildUnrollingMaps(simulation_.camera(), world_from_cam, grid, &map_x, &map_y);
    return UnrollFrame(frames_.Frame(index), map_x, map_y, valid);
  }

  Simulation simulation_;
  GainCorrectedFrames frames_;
};

TEST_F(UnrollSimulatedFrames, ConsecutiveFramesAgreeOnTheWall) {
  const UnrolledGrid grid = GridAround(0);
  const int other = 6;  // about 2 cm further along the pipe
  cv::Mat valid_a, valid_b;
  const cv::Mat a = Unroll(0, grid, simulation_.FramePose(0), &valid_a);
  const cv::Mat b = Unroll(other, grid, simulation_.FramePose(other), &valid_b);
  const cv::Mat both = valid_a & valid_b;
  const double overlap = cv::countNonZero(both) / static_cast<double>(grid.size.area());
  EXPECT_GT(overlap, 0.4);
  EXPECT_LT(overlap, 0.95);  // the frames moved
  EXPECT_GT(MaskedHighPassZncc(a, b, both), 0.95);

  // Control: a pose off by 1.5 mm along the pipe (5 cells) no longer lines up (ZNCC of the
  // fine texture, which a slow lighting residue cannot fake).
  Eigen::Isometry3d wrong = simulation_.FramePose(other);
  wrong.translation().z() += 0.0015;
  cv::Mat valid_c;
  const cv::Mat c = Unroll(other, grid, wrong, &valid_c);
  const cv::Mat both_c = valid_a & valid_c;
  EXPECT_LT(MaskedHighPassZncc(a, c, both_c), 0.5);
}

TEST_F(UnrollSimulatedFrames, MatchesTheWallTexture) {
  const UnrolledGrid grid = GridAround(10);
  cv::Mat valid;
  const cv::Mat unrolled = Unroll(10, grid, simulation_.FramePose(10), &valid);
  EXPECT_GT(cv::countNonZero(valid), grid.size.area() / 2);
  const cv::Mat albedo = SimulatedWallAlbedo(simulation_, grid);
  EXPECT_GT(MaskedHighPassZncc(unrolled, albedo, valid), 0.9);
  // Control: the texture one row (s) and three columns (h) off.
  const cv::Rect inner(3, 1, grid.size.width - 6, grid.size.height - 2);
  const double shifted =
      MaskedHighPassZncc(unrolled(inner), albedo(inner + cv::Point(3, 1)), valid(inner));
  EXPECT_LT(shifted, 0.5);
}

}  // namespace
}  // namespace pipescope
