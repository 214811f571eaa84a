// The renderer's ground truth is exact when a wall point seen at a pixel of one frame, carried
// into another frame with the true poses, the camera model and the scene, lands on the same
// texture there. Checked for every preset through every camera model.
#include "pipescope/synthetic/renderer.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>
#include <tuple>

#include "pipescope/synthetic/presets.h"
#include "pipescope/synthetic/simulation.h"

namespace pipescope {
namespace {

constexpr int kPatchRadius = 4;

// Removes the lighting's slow variation, which differs between frames because the LEDs move
// with the camera, leaving the texture.
cv::Mat HighPass(const cv::Mat& image) {
  cv::Mat blurred;
  cv::GaussianBlur(image, blurred, cv::Size(), 3.0);
  return image - blurred;
}

double Zncc(const cv::Mat& a, const cv::Mat& b) {
  cv::Scalar mean_a, std_a, mean_b, std_b;
  cv::meanStdDev(a, mean_a, std_a);
  cv::meanStdDev(b, mean_b, std_b);
  if (std_a[0] <= 0 || std_b[0] <= 0) return 0.0;
  return cv::mean((a - mean_a[0]).mul(b - mean_b[0]))[0] / (std_a[0] * std_b[0]);
}

// Points that move less than this between the frames are left out: they could not tell a
// right reprojection from a wrong one.
constexpr double kMinMotionPx = 1.5;

struct ReprojectionStats {
  int compared = 0;
  double mean_zncc = 0.0;
  double mean_zncc_shifted = 0.0;  // control: the same patches 3 px off
  double mean_zncc_static = 0.0;   // control: the same pixel in frame j, as if nothing moved
};

// Pixels that see lit wall, away from the image circle's rim and the dark far end by more than
// the high-pass filter's reach: there the edge, which does not move with the texture, would
// dominate the patches.
cv::Mat LitInterior(const cv::Mat& radiance) {
  cv::Mat lit = radiance > 0.0f;
  cv::erode(lit, lit, cv::Mat(), cv::Point(-1, -1), 12);
  return lit;
}

ReprojectionStats CompareFrames(const Simulation& simulation, int i, int j) {
  const cv::Mat radiance_i = simulation.RenderFrameRadiance(i);
  const cv::Mat radiance_j = simulation.RenderFrameRadiance(j);
  const cv::Mat lit_i = LitInterior(radiance_i);
  const cv::Mat lit_j = LitInterior(radiance_j);
  const cv::Mat image_i = HighPass(radiance_i);
  const cv::Mat image_j = HighPass(radiance_j);
  const Eigen::Isometry3d world_from_i = simulation.FramePose(i);
  const Eigen::Isometry3d j_from_world = simulation.FramePose(j).inverse();
  const Camera& camera = simulation.camera();
  const cv::Size patch_size(2 * kPatchRadius + 1, 2 * kPatchRadius + 1);
  const int margin = kPatchRadius + 4;
  ReprojectionStats stats;
  for (int y = margin; y < camera.Height() - margin; y += 6) {
    for (int x = margin; x < camera.Width() - margin; x += 6) {
      Eigen::Vector3d bearing;
      if (!lit_i.at<std::uint8_t>(y, x) || !camera.Unproject(Eigen::Vector2d(x, y), &bearing)) {
        continue;
      }
      const std::optional<WallHit> hit = simulation.layout().scene.Intersect(
          {world_from_i.translation(), world_from_i.linear() * bearing});
      if (!hit) continue;
      Eigen::Vector2d pixel_j;
      if (camera.Project(j_from_world * hit->point, &pixel_j) != ProjectionStatus::kValid) continue;
      if (pixel_j.x() < margin || pixel_j.y() < margin ||
          pixel_j.x() > camera.Width() - 1 - margin || pixel_j.y() > camera.Height() - 1 - margin) {
        continue;
      }
      // Seen from frame j too, not hidden behind another part of the wall.
      const Eigen::Vector3d origin_j = j_from_world.inverse().translation();
      const Eigen::Vector3d to_point = hit->point - origin_j;
      const std::optional<WallHit> hit_j =
          simulation.layout().scene.Intersect({origin_j, to_point.normalized()});
      if (!hit_j || std::abs(hit_j->distance - to_point.norm()) > 1e-6) continue;
      if ((pixel_j - Eigen::Vector2d(x, y)).norm() < kMinMotionPx) continue;
      if (!lit_j.at<std::uint8_t>(static_cast<int>(std::lround(pixel_j.y())),
                                  static_cast<int>(std::lround(pixel_j.x())))) {
        continue;
      }
      cv::Mat patch_i, patch_j, patch_shifted, patch_static;
      cv::getRectSubPix(image_i, patch_size, cv::Point2f(x, y), patch_i);
      cv::getRectSubPix(image_j, patch_size, cv::Point2f(pixel_j.x(), pixel_j.y()), patch_j);
      cv::getRectSubPix(image_j, patch_size, cv::Point2f(pixel_j.x() + 3, pixel_j.y()),
                        patch_shifted);
      cv::getRectSubPix(image_j, patch_size, cv::Point2f(x, y), patch_static);
      cv::Scalar mean, stddev;
      cv::meanStdDev(patch_i, mean, stddev);
      if (stddev[0] < 1e-4) continue;  // no texture to compare
      stats.mean_zncc += Zncc(patch_i, patch_j);
      stats.mean_zncc_shifted += Zncc(patch_i, patch_shifted);
      stats.mean_zncc_static += Zncc(patch_i, patch_static);
      ++stats.compared;
    }
  }
  if (stats.compared > 0) {
    stats.mean_zncc /= stats.compared;
    stats.mean_zncc_shifted /= stats.compared;
    stats.mean_zncc_static /= stats.compared;
  }
  return stats;
}

class RendererReprojectionTest
    : public ::testing::TestWithParam<std::tuple<std::string, std::string>> {};

TEST_P(RendererReprojectionTest, WallPointsLandOnTheSameTexture) {
  const auto& [preset, model] = GetParam();
  SimulationConfig config = PresetConfig(preset);
  config.camera_model = model;
  // A 190-degree lens spreads its pixels over the whole wall around it: it needs more of them
  // for patches of the same texture detail.
  const int scale = config.fov_deg >= 180.0 ? 2 : 1;
  config.width = 240 * scale;
  config.height = 180 * scale;
  if (model != "fisheye-poly") config.fov_deg = std::min(config.fov_deg, 100.0);
  config.frames = 40;
  config.stop_count = 0;  // the frames compared must be apart in space
  // Highlights move over the wall with the viewpoint (as they should); the texture does not.
  config.specular_strength = 0.0;
  const Simulation simulation(config);
  // Frames a tenth of the radius of travel apart: the texture moves by pixels, not so far that
  // the patches warp much.
  const int offset = std::max(
      2, static_cast<int>(std::lround(0.1 * config.radius_m * config.fps / config.speed_m_s)));
  const ReprojectionStats stats = CompareFrames(simulation, 10, 10 + offset);
  std::printf("%s %s: %d patches, mean ZNCC %.3f (3 px off: %.3f, not moved: %.3f)\n",
              preset.c_str(), model.c_str(), stats.compared, stats.mean_zncc,
              stats.mean_zncc_shifted, stats.mean_zncc_static);
  ASSERT_GT(stats.compared, 50);
  EXPECT_GT(stats.mean_zncc, 0.9);
  EXPECT_LT(stats.mean_zncc_shifted, 0.6);
  EXPECT_LT(stats.mean_zncc_static, stats.mean_zncc - 0.2);
}

INSTANTIATE_TEST_SUITE_P(
    EveryPresetEveryModel, RendererReprojectionTest,
    ::testing::Combine(::testing::Values("steel-6in", "steel-16in", "fiberglass-network", "culvert",
                                         "tube-bend"),
                       ::testing::Values("pinhole-radtan", "kannala-brandt", "fisheye-poly")),
    [](const auto& info) {
      std::string name = std::get<0>(info.param) + "_" + std::get<1>(info.param);
      std::replace(name.begin(), name.end(), '-', '_');
      return name;
    });

}  // namespace
}  // namespace pipescope

namespace pipescope {
namespace {

TEST(Renderer, ImageDoesNotDependOnTheThreadCount) {
  SimulationConfig config = PresetConfig("fiberglass-network");
  config.width = 200;
  config.height = 150;
  config.frames = 2;
  const Simulation simulation(config);
  const int threads = cv::getNumThreads();
  cv::setNumThreads(1);
  const cv::Mat one_thread = simulation.RenderFrameRadiance(1);
  cv::setNumThreads(4);
  const cv::Mat four_threads = simulation.RenderFrameRadiance(1);
  cv::setNumThreads(threads);
  EXPECT_GT(cv::norm(one_thread, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(one_thread, four_threads, cv::NORM_INF), 0.0);
}

}  // namespace
}  // namespace pipescope
