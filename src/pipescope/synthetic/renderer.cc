#include "pipescope/synthetic/renderer.h"

#include <algorithm>
#include <cmath>
#include <opencv2/core/utility.hpp>
#include <utility>

namespace pipescope {
namespace {

// Grazing views stretch a pixel's footprint by 1 / cos(incidence); cap the stretch so the
// texture filter stays sharp enough to be useful there.
constexpr double kMinFootprintCosine = 0.1;

}  // namespace

Renderer::Renderer(const Camera& camera, const Scene& scene, const WallTexture& texture,
                   const Lighting& lighting, double max_view_angle)
    : camera_(camera), scene_(scene), texture_(texture), lighting_(lighting) {
  const double min_cos_angle = std::cos(std::min(max_view_angle, camera.MaxAngle()));
  const int width = camera.Width();
  const int height = camera.Height();
  bearings_.assign(static_cast<std::size_t>(width) * height, Eigen::Vector3d::Zero());
  pixel_angle_.assign(bearings_.size(), 0.0f);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      Eigen::Vector3d bearing;
      if (camera.Unproject(Eigen::Vector2d(x, y), &bearing) && bearing.z() >= min_cos_angle) {
        bearings_[static_cast<std::size_t>(y) * width + x] = bearing;
      }
    }
  }
  // A pixel's angular size: the largest angle to the bearing of a valid 4-neighbour, so pixels
  // at the rim of a fisheye's image circle still get a footprint (and a filtered texture).
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * width + x;
      const Eigen::Vector3d& b = bearings_[i];
      if (b.isZero()) continue;
      double angle = 0.0;
      for (const auto& [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
        const int nx = x + dx;
        const int ny = y + dy;
        if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
        const Eigen::Vector3d& neighbour = bearings_[static_cast<std::size_t>(ny) * width + nx];
        if (!neighbour.isZero()) {
          angle = std::max(angle, std::acos(std::clamp(b.dot(neighbour), -1.0, 1.0)));
        }
      }
      pixel_angle_[i] = static_cast<float>(angle);
    }
  }
}

void Renderer::RenderRows(const Eigen::Isometry3d& world_from_cam, const RenderSettings& settings,
                          int row_begin, int row_end, cv::Mat* radiance) const {
  const Eigen::Matrix3d rotation = world_from_cam.linear();
  const Eigen::Matrix3d rotation_t = rotation.transpose();
  const Eigen::Vector3d origin = world_from_cam.translation();
  const int width = camera_.Width();
  const bool uniform = settings.uniform_albedo >= 0.0f;
  const auto uniform_specularity =
      static_cast<float>(settings.specular_strength * settings.uniform_specularity);
  // A row goes through three passes: cast every pixel's ray, texture every hit, light them all
  // (SIMD across pixels). Each pixel is one long chain of dependent square roots, divisions and
  // lookups; in short separate loops the CPU overlaps the chains of neighbouring pixels, which
  // made the row about a third faster than one pass per pixel. The buffers live per thread: the
  // work is split into many small row ranges.
  struct Scratch {
    std::vector<WallHit> hits;
    std::vector<int> columns;
    std::vector<double> footprints;
    ShadingBatch batch;
    std::vector<float> shaded;
  };
  thread_local Scratch scratch;
  scratch.hits.resize(width);
  scratch.columns.resize(width);
  scratch.footprints.resize(width);
  scratch.shaded.resize(width);
  ShadingBatch& batch = scratch.batch;
  const Scene::RayFan fan(scene_, origin);
  for (int y = row_begin; y < row_end; ++y) {
    // Cast.
    int count = 0;
    for (int x = 0; x < width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * width + x;
      const Eigen::Vector3d& bearing = bearings_[i];
      if (bearing.isZero()) continue;
      const Eigen::Vector3d direction = rotation * bearing;
      WallHit& hit = scratch.hits[count];
      if (!fan.Intersect(direction, &hit)) continue;
      const double cosine = std::abs(direction.dot(hit.normal));
      scratch.footprints[count] =
          hit.distance * pixel_angle_[i] / std::max(cosine, kMinFootprintCosine);
      scratch.columns[count++] = x;
    }
    // Texture, and the wall point in the camera frame for the light.
    batch.Resize(count);
    for (int k = 0; k < count; ++k) {
      const WallHit& hit = scratch.hits[k];
      const double footprint = scratch.footprints[k];
      float albedo = settings.uniform_albedo;
      float specularity = uniform_specularity;
      if (!uniform) {
        const double circumference = 2.0 * M_PI * scene_.sections()[hit.section].radius;
        const WallSample sample =
            texture_.Sample(hit.section, hit.h_m, hit.s_m, circumference, footprint);
        albedo = sample.albedo;
        specularity = static_cast<float>(settings.specular_strength * sample.specularity);
        if (settings.scale_target != nullptr) {
          settings.scale_target->Paint(hit.section, hit.h_m, hit.s_m, footprint, &albedo,
                                       &specularity);
        }
      }
      // The hit is origin + distance * rotation * bearing, so in the camera frame it lies at
      // distance * bearing.
      const Eigen::Vector3d& bearing =
          bearings_[static_cast<std::size_t>(y) * width + scratch.columns[k]];
      const Eigen::Vector3d normal_cam = rotation_t * hit.normal;
      const float point[3] = {static_cast<float>(hit.distance * bearing.x()),
                              static_cast<float>(hit.distance * bearing.y()),
                              static_cast<float>(hit.distance * bearing.z())};
      const float normal[3] = {static_cast<float>(normal_cam.x()),
                               static_cast<float>(normal_cam.y()),
                               static_cast<float>(normal_cam.z())};
      batch.Set(k, point, normal, albedo, specularity);
    }
    // Light.
    lighting_.Shade(batch, scratch.shaded.data());
    float* out = radiance->ptr<float>(y);
    std::fill(out, out + width, 0.0f);
    for (int k = 0; k < count; ++k) out[scratch.columns[k]] = scratch.shaded[k];
  }
}

cv::Mat Renderer::RenderRadiance(const Eigen::Isometry3d& world_from_cam,
                                 const RenderSettings& settings) const {
  cv::Mat radiance(camera_.Height(), camera_.Width(), CV_32F);
  // Rows are independent, so any split over threads gives the same image.
  cv::parallel_for_(cv::Range(0, camera_.Height()), [&](const cv::Range& rows) {
    RenderRows(world_from_cam, settings, rows.start, rows.end, &radiance);
  });
  return radiance;
}

}  // namespace pipescope
