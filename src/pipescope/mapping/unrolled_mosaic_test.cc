#include "pipescope/mapping/unrolled_mosaic.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "pipescope/image/unrolling_testing.h"

namespace pipescope {
namespace {

Eigen::Isometry3d PoseFromAxes(const Eigen::Vector3d& x, const Eigen::Vector3d& y,
                               const Eigen::Vector3d& z, const Eigen::Vector3d& position) {
  Eigen::Isometry3d world_from_cam = Eigen::Isometry3d::Identity();
  world_from_cam.linear().col(0) = x;
  world_from_cam.linear().col(1) = y;
  world_from_cam.linear().col(2) = z;
  world_from_cam.translation() = position;
  return world_from_cam;
}

TEST(UnrolledMosaic, GridCoversTheCircumference) {
  const Camera camera(CameraModelId::kPinholeRadtan, 64, 48, {50, 50, 31.5, 23.5, 0, 0, 0, 0, 0});
  const UnrolledMosaic mosaic(camera, 0.1, 0.001, -0.5, 1.5);
  EXPECT_EQ(mosaic.grid().size, cv::Size(2001, 629));  // ceil(2 pi 100)
  EXPECT_EQ(mosaic.grid().h0_m, -0.5);
  EXPECT_EQ(mosaic.grid().s0_m, 0.0);
  EXPECT_TRUE(mosaic.CoveredRegion().empty());
  const cv::Mat empty = mosaic.Render();
  EXPECT_EQ(empty.size(), mosaic.grid().size);
  EXPECT_EQ(cv::countNonZero(empty == empty), 0);  // all NaN
}

// Restricting each frame to its footprint loses no cell: the mosaic of one frame equals the
// frame unrolled onto the whole grid (within the axial range), across the s = 0 seam and for a
// forward-looking fisheye that sees the whole circumference.
struct FootprintCase {
  const char* name;
  CameraModelId model;
  std::vector<double> params;
  Eigen::Isometry3d world_from_cam;
};

class UnrolledMosaicFootprint : public testing::TestWithParam<int> {};

TEST_P(UnrolledMosaicFootprint, LosesNoCell) {
  const double radius = 0.2;
  const FootprintCase cases[] = {
      {"wall-looking across the seam",
       CameraModelId::kPinholeRadtan,
       {200, 200, 159.5, 119.5, 0.05, 0, 0, 0, 0},
       // Optical axis +X (phi = 0), image x along the pipe.
       PoseFromAxes(Eigen::Vector3d::UnitZ(), -Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitX(),
                    {0.02, 0.01, 0.3})},
      {"forward fisheye",
       CameraModelId::kKannalaBrandt,
       {90, 90, 159.5, 119.5, 0.01, 0, 0, 0},
       PoseFromAxes(Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ(),
                    {0.03, -0.02, 0.3})},
  };
  const FootprintCase& test_case = cases[GetParam()];
  SCOPED_TRACE(test_case.name);
  const Camera camera(test_case.model, 320, 240, test_case.params);
  cv::Mat frame(240, 320, CV_32F);
  cv::RNG rng(3);
  rng.fill(frame, cv::RNG::UNIFORM, 0.0, 1.0);

  const double pixel = 0.002;
  // Every cell projected, so that the footprint's cells equal the full map's exactly.
  UnrolledMosaicOptions options;
  options.map_lattice_cells = 1;
  UnrolledMosaic mosaic(camera, radius, pixel, -0.5, 1.5, options);
  mosaic.Add(frame, test_case.world_from_cam);
  const cv::Mat rendered = mosaic.Render();

  cv::Mat map_x, map_y, valid;
  BuildUnrollingMaps(camera, test_case.world_from_cam, mosaic.grid(), &map_x, &map_y);
  const cv::Mat full = UnrollFrame(frame, map_x, map_y, &valid);
  const double h_camera = test_case.world_from_cam.translation().z();
  const double range = 3.0 * radius;  // the default
  int compared = 0, covered = 0;
  for (int v = 0; v < rendered.rows; ++v) {
    for (int u = 0; u < rendered.cols; ++u) {
      const float value = rendered.at<float>(v, u);
      const bool seen = valid.at<uchar>(v, u) != 0;
      if (!std::isnan(value)) {
        ++covered;
        ASSERT_TRUE(seen) << u << " " << v;
        ASSERT_EQ(value, full.at<float>(v, u)) << u << " " << v;
      }
      const double h = mosaic.grid().h0_m + u * pixel;
      if (seen && std::abs(h - h_camera) < 0.95 * range) {
        ++compared;
        ASSERT_FALSE(std::isnan(value)) << u << " " << v;
      }
    }
  }
  EXPECT_GT(compared, 2000);
  // Both sides of the seam, or the whole circumference.
  const cv::Rect region = mosaic.CoveredRegion();
  EXPECT_EQ(region.y, 0);
  EXPECT_EQ(region.br().y, mosaic.grid().size.height);
  EXPECT_GE(covered, compared);
}

INSTANTIATE_TEST_SUITE_P(Cameras, UnrolledMosaicFootprint, testing::Values(0, 1));

// Two mosaics of one simulated pass, from the even and from the odd frames at their true poses,
// show the same wall: the unrolling and the stitching put every frame in its place.
TEST(UnrolledMosaic, HalvesOfASimulatedPassAgree) {
  const Simulation simulation(SmallSteelConfig(192, 144, 36));
  const GainCorrectedFrames frames(simulation);
  const double radius = simulation.config().radius_m;
  const double pixel = 0.0005;  // about two image pixels
  const double h_first = simulation.FramePose(0).translation().z();
  const double h_last = simulation.FramePose(35).translation().z();
  UnrolledMosaic even(simulation.camera(), radius, pixel, h_first - 0.05, h_last + 0.05);
  UnrolledMosaic odd(simulation.camera(), radius, pixel, h_first - 0.05, h_last + 0.05);
  for (int k = 0; k < 36; ++k) {
    (k % 2 == 0 ? even : odd).Add(frames.Frame(k), simulation.FramePose(k));
  }
  EXPECT_EQ(even.frames_added(), 18);
  // A wall-looking camera sees a band around phi = 90 degrees (s = r pi / 2).
  const cv::Rect region = even.CoveredRegion();
  EXPECT_NEAR((region.y + 0.5 * region.height) * pixel, radius * M_PI / 2, 0.01);
  EXPECT_LT(region.height, even.grid().size.height / 4);

  const cv::Rect common = region & odd.CoveredRegion();
  const cv::Mat a = even.Render(common);
  const cv::Mat b = odd.Render(common);
  const cv::Mat both = (a == a) & (b == b);
  EXPECT_GT(cv::countNonZero(both), common.area() / 2);
  EXPECT_GT(MaskedHighPassZncc(a, b, both), 0.97);
  // Control: two cells (1 mm) off along the pipe.
  const cv::Mat shifted = odd.Render(common + cv::Point(2, 0));
  EXPECT_LT(MaskedHighPassZncc(a, shifted, both & (shifted == shifted)), 0.6);
}

// The default mosaic (unrolling maps interpolated on a lattice) against the one that projects
// every cell, over a simulated pass at the camera's own ground resolution: the same cells, the
// same values to a small fraction of the texture's contrast, and both register with the
// simulator's wall texture.
TEST(UnrolledMosaic, LatticeMapsAgreeWithEveryCellProjected) {
  const Simulation simulation(SmallSteelConfig(320, 240, 24));
  const GainCorrectedFrames frames(simulation);
  const double radius = simulation.config().radius_m;
  const double pixel = 1.0 / 3700.0;  // 1 / zeta of this camera (~3725 px/m)
  const double h_first = simulation.FramePose(0).translation().z();
  const double h_last = simulation.FramePose(23).translation().z();
  UnrolledMosaicOptions exact_options;
  exact_options.map_lattice_cells = 1;
  UnrolledMosaic exact(simulation.camera(), radius, pixel, h_first - 0.05, h_last + 0.05,
                       exact_options);
  UnrolledMosaic lattice(simulation.camera(), radius, pixel, h_first - 0.05, h_last + 0.05);
  for (int k = 0; k < 24; k += 3) {
    const cv::Mat frame = frames.Frame(k);
    exact.Add(frame, simulation.FramePose(k));
    lattice.Add(frame, simulation.FramePose(k));
  }
  const cv::Rect region = exact.CoveredRegion();
  ASSERT_EQ(lattice.CoveredRegion(), region);
  const cv::Mat a = exact.Render(region);
  const cv::Mat b = lattice.Render(region);
  const cv::Mat seen_a = a == a, seen_b = b == b;
  const int covered = cv::countNonZero(seen_a);
  EXPECT_GT(covered, region.area() / 2);
  // Only where the interpolation moves a cell across the image's edge.
  EXPECT_LE(cv::countNonZero(seen_a != seen_b), covered / 10000);
  const cv::Mat both = seen_a & seen_b;
  cv::Scalar mean, contrast;
  cv::meanStdDev(a, mean, contrast, both);
  const double mean_difference = cv::mean(cv::abs(a - b), both)[0];
  double largest_difference = 0.0;
  cv::minMaxLoc(cv::abs(a - b), nullptr, &largest_difference, nullptr, nullptr, both);
  std::printf("%d cells, texture sd %.4f, mean |difference| %.6f, largest %.6f\n", covered,
              contrast[0], mean_difference, largest_difference);
  EXPECT_LT(mean_difference, 1e-3 * contrast[0]);

  UnrolledGrid grid = exact.grid();
  grid.h0_m += region.x * pixel;
  grid.s0_m += region.y * pixel;
  grid.size = region.size();
  const cv::Mat albedo = SimulatedWallAlbedo(simulation, grid);
  const double zncc_exact = MaskedHighPassZncc(a, albedo, both);
  const double zncc_lattice = MaskedHighPassZncc(b, albedo, both);
  EXPECT_GT(zncc_lattice, 0.9);
  EXPECT_NEAR(zncc_lattice, zncc_exact, 1e-4);
}

}  // namespace
}  // namespace pipescope
