#include "pipescope/synthetic/simulated_camera.h"

#include <cmath>

namespace pipescope {
namespace {
constexpr double kDegToRad = M_PI / 180.0;
}  // namespace

Camera MakeSimulatedCamera(const SimulationConfig& c) {
  const double half_fov = 0.5 * c.fov_deg * kDegToRad;
  const double cx = 0.5 * (c.width - 1);
  const double cy = 0.5 * (c.height - 1);
  const double half_width = 0.5 * c.width;
  if (c.camera_model == "pinhole-radtan") {
    const double f = half_width / std::tan(half_fov);
    // k1 scaled so the corner moves inwards by `distortion` of its radius; the radial map stays
    // monotonic over the image while 1 + 3 k1 r^2 > 0, i.e. distortion < 1/3.
    const double corner_r2 = (cx * cx + cy * cy) / (f * f);
    const double k1 = -c.distortion / corner_r2;
    return Camera(CameraModelId::kPinholeRadtan, c.width, c.height,
                  {f, f, cx, cy, k1, 0.0, 0.0, 0.0, 0.0});
  }
  if (c.camera_model == "kannala-brandt") {
    const double f = half_width / half_fov;
    return Camera(CameraModelId::kKannalaBrandt, c.width, c.height,
                  {f, f, cx, cy, -0.1 * c.distortion, 0.0, 0.0, 0.0});
  }
  const double cubic = -0.2 * c.distortion;
  const double rim_px = c.fov_deg >= 180.0 ? 0.49 * c.height : half_width;
  const double k1 = rim_px / (half_fov + cubic * half_fov * half_fov * half_fov);
  return Camera(CameraModelId::kFisheyePoly, c.width, c.height, {k1, cubic * k1, 0.0, 0.0, cx, cy});
}

Eigen::Isometry3d BodyFromCam(const SimulationConfig& config) {
  Eigen::Isometry3d body_from_cam = Eigen::Isometry3d::Identity();
  if (config.view == "wall") {
    // Columns: the camera's x, y, z axes in body coordinates.
    Eigen::Matrix3d rotation;
    rotation.col(0) = Eigen::Vector3d::UnitZ();
    rotation.col(1) = Eigen::Vector3d::UnitX();
    rotation.col(2) = Eigen::Vector3d::UnitY();
    body_from_cam.linear() = rotation;
  }
  body_from_cam.translation() = Eigen::Vector3d(0.0, -config.mount_offset_m, 0.0);
  return body_from_cam;
}

std::optional<double> ReferenceScalePxPerM(const SimulationConfig& config, const Camera& camera) {
  if (config.view != "wall") return std::nullopt;
  const double distance_to_wall = config.radius_m + config.mount_offset_m;
  return CentralFocalLengthPx(camera) / distance_to_wall;
}

}  // namespace pipescope
