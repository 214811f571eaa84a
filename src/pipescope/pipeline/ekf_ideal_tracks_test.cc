// The tubular EKF (004) through the tube-bend preset's true geometry and motion with ideal
// tracks: wall points of the simulator's scene, seen where the true poses put them (occlusion by
// the scene's own ray casting) plus 0.3 px of noise. Separates what the filter does in a bend
// from what the image tracking adds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "pipescope/estimation/tubular_ekf.h"
#include "pipescope/synthetic/presets.h"
#include "pipescope/synthetic/simulation.h"

namespace pipescope {
namespace {

// Whether the wall point is what the camera at `position` sees in its direction.
bool Visible(const Scene& scene, const Eigen::Vector3d& position, const Eigen::Vector3d& point) {
  Ray ray;
  ray.origin = position;
  ray.direction = (point - position).normalized();
  const std::optional<WallHit> hit = scene.Intersect(ray);
  return hit && std::abs(hit->distance - (point - position).norm()) < 1e-6;
}

double AngleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 / M_PI;
}

TEST(EkfIdealTracks, FollowsTheTubeBend) {
  SimulationConfig config = PresetConfig("tube-bend");
  config.frames = 700;
  const Simulation simulation(config);
  const Scene& scene = simulation.layout().scene;
  const Camera& camera = simulation.camera();
  std::mt19937 random(3);
  std::normal_distribution<double> noise(0.0, 0.3);

  // Wall points: what a grid of pixels sees from every 5th frame.
  std::vector<Eigen::Vector3d> points;
  for (int k = 0; k < config.frames; k += 10) {
    const Eigen::Isometry3d pose = simulation.FramePose(k);
    for (int v = 10; v < camera.Height(); v += 30) {
      for (int u = 10; u < camera.Width(); u += 30) {
        Eigen::Vector3d bearing;
        if (!camera.Unproject(Eigen::Vector2d(u, v), &bearing)) continue;
        Ray ray;
        ray.origin = pose.translation();
        ray.direction = pose.rotation() * bearing;
        if (const auto hit = scene.Intersect(ray); hit && hit->distance < 0.6) {
          points.push_back(hit->point);
        }
      }
    }
  }

  const double dt = 1.0 / config.fps;
  TubularEkf filter(camera, simulation.FramePose(0), Eigen::Vector3d::UnitZ(), config.radius_m, {});
  for (int k = 1; k < config.frames; ++k) {
    const Eigen::Isometry3d previous = simulation.FramePose(k - 1);
    const Eigen::Isometry3d current = simulation.FramePose(k);
    std::vector<TubularEkfMatch> matches;
    for (std::size_t i = 0; i < points.size(); ++i) {
      Eigen::Vector2d a, b;
      const Eigen::Vector3d in_previous = previous.inverse() * points[i];
      if (in_previous.z() > 0.6) continue;
      if (camera.Project(in_previous, &a) != ProjectionStatus::kValid ||
          camera.Project(current.inverse() * points[i], &b) != ProjectionStatus::kValid) {
        continue;
      }
      if (!Visible(scene, previous.translation(), points[i]) ||
          !Visible(scene, current.translation(), points[i])) {
        continue;
      }
      TubularEkfMatch match;
      camera.Unproject(a + Eigen::Vector2d(noise(random), noise(random)), &match.previous_bearing);
      match.pixel = b + Eigen::Vector2d(noise(random), noise(random));
      match.track_id = static_cast<long>(i);
      matches.push_back(match);
    }
    filter.Predict(dt);
    filter.Update(matches);
  }
  const Eigen::Vector3d first_axis = filter.Sections().front().geometry.axis;
  // The last section's direction where the camera ended (it may bend).
  const TubeSection& last = filter.Sections().back().geometry;
  const Eigen::Vector3d last_axis =
      last.TangentAt(last.ArcCoordinate(filter.WorldFromCam().translation()));
  const double bend = AngleDeg(first_axis, last_axis);
  const double heading_true = AngleDeg(simulation.FramePose(0).rotation().col(2),
                                       simulation.FramePose(config.frames - 1).rotation().col(2));
  const double heading =
      AngleDeg(simulation.FramePose(0).rotation().col(2), filter.WorldFromCam().rotation().col(2));
  const double end_error_m =
      (filter.WorldFromCam().translation() - simulation.FramePose(config.frames - 1).translation())
          .norm();
  std::printf(
      "sections %zu bend %.2f deg; camera heading change %.2f deg (truth %.2f), %.1f mm off; the "
      "bend's section %.3f / m\n",
      filter.Sections().size(), bend, heading, heading_true, 1000.0 * end_error_m,
      filter.Sections().size() > 1 ? filter.Sections()[1].geometry.curvature.norm() : 0.0);
  // Measured with sections that bend (torus segments): 92.3 degrees of the true 90.3 (heading
  // 91.2), the camera 26 mm off after 2.3 m; the bend's own section 1.98 / m (truth 2.0). The
  // first section takes up a curvature of 0.09 / m from the bend ahead before the second starts,
  // which tilts its start. With straight sections only (curvature_sigma_radii 0): 88.7 (heading
  // 89.6), 37 mm; 85.1 (heading 85.6) when every feature counts fully (far_feature_radii 0), and
  // 167 mm off with the new sections' radius freer (new_section_radius_sigma 0.05).
  EXPECT_NEAR(bend, 90.0, 3.0);
  EXPECT_NEAR(heading, heading_true, 2.0);
  EXPECT_LT(end_error_m, 0.06);
}

}  // namespace
}  // namespace pipescope
