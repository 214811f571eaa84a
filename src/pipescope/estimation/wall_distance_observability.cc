#include "pipescope/estimation/wall_distance_observability.h"

#include <Eigen/Dense>
#include <cmath>
#include <optional>
#include <vector>

#include "pipescope/geometry/pipe_cylinder.h"
#include "pipescope/image/undistortion.h"
#include "pipescope/util/error.h"

namespace pipescope {
namespace {

// The second view's motion from the first: along the wall normal n, sideways s, along the axis,
// and a small rotation in the camera's own frame.
using Motion = Eigen::Matrix<double, 6, 1>;  // (a_n, a_s, travel, rx, ry, rz)

// The first view's grid pixels back-projected onto the wall from `origin`.
std::vector<Eigen::Vector3d> WallPointsOfGrid(const std::vector<Eigen::Vector2d>& pixels,
                                              const Camera& camera, const Eigen::Matrix3d& rotation,
                                              const Eigen::Vector3d& origin, double radius_m) {
  std::vector<Eigen::Vector3d> points;
  for (const Eigen::Vector2d& pixel : pixels) {
    Eigen::Vector3d bearing;
    std::optional<double> t;
    if (camera.Unproject(pixel, &bearing)) t = RayToWall(origin, rotation * bearing, radius_m);
    points.push_back(t ? Eigen::Vector3d(origin + *t * (rotation * bearing))
                       : Eigen::Vector3d::Constant(std::nan("")));
  }
  return points;
}

struct Frame {
  Eigen::Vector3d normal;    // towards the wall the camera faces, in the cross-section
  Eigen::Vector3d sideways;  // axis x normal
};

// Pixels of `points` seen from the first view's camera moved by `motion`: NaN for a point that
// is behind the camera or outside its field of view, and, with `on_image_only`, off the image.
std::vector<Eigen::Vector2d> ProjectAfter(const Camera& camera, const Eigen::Isometry3d& first,
                                          const Frame& frame, const Motion& motion,
                                          const std::vector<Eigen::Vector3d>& points,
                                          bool on_image_only) {
  const Eigen::Vector3d centre = first.translation() + motion[0] * frame.normal +
                                 motion[1] * frame.sideways + motion[2] * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d rotation_vector = motion.tail<3>();
  const double angle = rotation_vector.norm();
  const Eigen::Matrix3d turn =
      angle > 0.0 ? Eigen::AngleAxisd(angle, rotation_vector / angle).toRotationMatrix()
                  : Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d cam_from_world = (first.linear() * turn).transpose();
  std::vector<Eigen::Vector2d> pixels;
  for (const Eigen::Vector3d& point : points) {
    Eigen::Vector2d pixel = Eigen::Vector2d::Constant(std::nan(""));
    if (point.allFinite()) {
      const ProjectionStatus status = camera.Project(cam_from_world * (point - centre), &pixel);
      const bool keep = status == ProjectionStatus::kValid ||
                        (!on_image_only && status == ProjectionStatus::kOutsideImage);
      if (!keep) pixel = Eigen::Vector2d::Constant(std::nan(""));
    }
    pixels.push_back(pixel);
  }
  return pixels;
}

// The pixels of the points in `use`, stacked.
Eigen::VectorXd Stacked(const std::vector<Eigen::Vector2d>& pixels, const std::vector<int>& use) {
  Eigen::VectorXd stacked(2 * use.size());
  for (std::size_t k = 0; k < use.size(); ++k) stacked.segment<2>(2 * k) = pixels[use[k]];
  return stacked;
}

}  // namespace

WallDistanceObservability AssessWallDistanceObservability(
    const Camera& camera, const Eigen::Isometry3d& start_world_from_cam, double radius_m,
    const WallDistanceObservabilityOptions& options) {
  const Eigen::Vector3d optical_axis = start_world_from_cam.linear().col(2);
  Frame frame;
  frame.normal = Eigen::Vector3d(optical_axis.x(), optical_axis.y(), 0.0);
  if (frame.normal.norm() < 0.1) {
    throw InputError("wall-distance observability: the camera does not face the wall");
  }
  frame.normal.normalize();
  frame.sideways = Eigen::Vector3d::UnitZ().cross(frame.normal);
  const Eigen::Vector3d origin = start_world_from_cam.translation();
  const std::optional<double> wall_distance = RayToWall(origin, frame.normal, radius_m);
  if (!wall_distance)
    throw InputError("wall-distance observability: the camera is not in the pipe");

  WallDistanceObservability result;
  const double extent_m =
      *wall_distance * std::max(camera.Width(), camera.Height()) / CentralFocalLengthPx(camera);
  result.step_m = extent_m / 3.0;

  std::vector<Eigen::Vector2d> grid;
  for (int row = 0; row < options.grid; ++row) {
    for (int col = 0; col < options.grid; ++col) {
      const double u = 0.05 + 0.9 * col / (options.grid - 1.0);
      const double v = 0.05 + 0.9 * row / (options.grid - 1.0);
      grid.emplace_back(u * (camera.Width() - 1), v * (camera.Height() - 1));
    }
  }
  // Hypothesis 0: the camera where it is; hypothesis 1: `nearer` closer to the wall. The step is
  // along the pipe's axis in the pipe's frame, whatever way the camera is mounted.
  const double nearer_m = 1e-4;
  const std::vector<Eigen::Vector3d> points0 =
      WallPointsOfGrid(grid, camera, start_world_from_cam.linear(), origin, radius_m);
  Eigen::Isometry3d nearer_start = start_world_from_cam;
  nearer_start.translation() += nearer_m * frame.normal;
  const std::vector<Eigen::Vector3d> points1 =
      WallPointsOfGrid(grid, camera, nearer_start.linear(), nearer_start.translation(), radius_m);
  Motion step = Motion::Zero();
  step[2] = result.step_m;
  // The grid pixels both hypotheses see on the image in the second view.
  const std::vector<Eigen::Vector2d> seen0 =
      ProjectAfter(camera, start_world_from_cam, frame, step, points0, true);
  const std::vector<Eigen::Vector2d> seen1 =
      ProjectAfter(camera, nearer_start, frame, step, points1, true);
  std::vector<int> use;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    if (seen0[i].allFinite() && seen1[i].allFinite()) use.push_back(static_cast<int>(i));
  }
  result.pixels = static_cast<int>(use.size());
  if (result.pixels < 12) {
    throw InputError(
        "wall-distance observability: fewer than 12 pixels see the wall in both views");
  }
  const Eigen::VectorXd pixels0 = Stacked(seen0, use);
  const Eigen::VectorXd pixels1 = Stacked(seen1, use);
  // The second view's motion, linearised about the step, mimics what it can of the difference.
  Eigen::MatrixXd jacobian(pixels1.size(), 6);
  for (int k = 0; k < 6; ++k) {
    const double h = k < 3 ? 1e-6 : 1e-6 / radius_m;
    Motion plus = step, minus = step;
    plus[k] += h;
    minus[k] -= h;
    jacobian.col(k) =
        (Stacked(ProjectAfter(camera, nearer_start, frame, plus, points1, false), use) -
         Stacked(ProjectAfter(camera, nearer_start, frame, minus, points1, false), use)) /
        (2.0 * h);
  }
  const Eigen::VectorXd difference = pixels0 - pixels1;
  const Eigen::VectorXd mimicked = jacobian * jacobian.colPivHouseholderQr().solve(difference);
  const double left_px = std::sqrt((difference - mimicked).squaredNorm() / result.pixels);
  result.parallax_px_per_mm = left_px / (1000.0 * nearer_m);
  result.wall_distance_sigma_mm =
      options.pixel_sigma_px / (result.parallax_px_per_mm * std::sqrt(options.features));
  result.scale_sigma_pct = 100.0 * result.wall_distance_sigma_mm / (1000.0 * *wall_distance);
  result.observable = result.scale_sigma_pct <= options.max_scale_sigma_pct;
  return result;
}

}  // namespace pipescope
