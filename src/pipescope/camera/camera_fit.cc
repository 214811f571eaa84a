#include "pipescope/camera/camera_fit.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace pipescope {
namespace {

// Kannala-Brandt's projection of a fixed direction minus the source camera's pixel.
struct ProjectionResidual {
  ProjectionResidual(const Eigen::Vector3d& direction, const Eigen::Vector2d& pixel)
      : direction_(direction), pixel_(pixel) {}

  template <typename T>
  bool operator()(const T* params, T* residual) const {
    const T point[3] = {T(direction_.x()), T(direction_.y()), T(direction_.z())};
    T pixel[2];
    KannalaBrandtModel::ProjectPoint(params, point, pixel);
    residual[0] = pixel[0] - pixel_.x();
    residual[1] = pixel[1] - pixel_.y();
    return true;
  }

  Eigen::Vector3d direction_;
  Eigen::Vector2d pixel_;
};

}  // namespace

KannalaBrandtFit FitKannalaBrandt(const Camera& source, const KannalaBrandtFitOptions& options) {
  if (!(options.max_angle > 0 && options.max_angle < M_PI / 2)) {
    throw std::invalid_argument("FitKannalaBrandt: max_angle outside (0, pi/2)");
  }
  if (options.num_angles < 1 || options.num_azimuths < 1 ||
      options.num_angles * options.num_azimuths < 8) {
    throw std::invalid_argument("FitKannalaBrandt: fewer samples than the 8 parameters");
  }
  std::vector<Eigen::Vector3d> directions;
  std::vector<Eigen::Vector2d> pixels;
  for (int i = 1; i <= options.num_angles; ++i) {
    const double theta = options.max_angle * i / options.num_angles;
    for (int j = 0; j < options.num_azimuths; ++j) {
      const double phi = 2 * M_PI * j / options.num_azimuths;
      const Eigen::Vector3d direction(std::sin(theta) * std::cos(phi),
                                      std::sin(theta) * std::sin(phi), std::cos(theta));
      Eigen::Vector2d pixel;
      const ProjectionStatus status = source.Project(direction, &pixel);
      // Off-image pixels still describe the lens; directions past its field of view do not.
      if (status == ProjectionStatus::kValid || status == ProjectionStatus::kOutsideImage) {
        directions.push_back(direction);
        pixels.push_back(pixel);
      }
    }
  }
  if (directions.size() < 8) {
    throw std::invalid_argument("FitKannalaBrandt: the source projects fewer than 8 samples");
  }

  // Start from an equidistant lens with the source's axis pixel and its focal length there.
  Eigen::Vector2d centre;
  Eigen::Vector2d near_axis;
  constexpr double kNearAxis = 1e-3;
  source.Project(Eigen::Vector3d(0, 0, 1), &centre);
  source.Project(Eigen::Vector3d(std::sin(kNearAxis), 0, std::cos(kNearAxis)), &near_axis);
  const double focal = (near_axis - centre).norm() / kNearAxis;
  double params[8] = {focal, focal, centre.x(), centre.y(), 0, 0, 0, 0};

  ceres::Problem problem;
  for (std::size_t i = 0; i < directions.size(); ++i) {
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<ProjectionResidual, 2, 8>(
                                 new ProjectionResidual(directions[i], pixels[i])),
                             nullptr, params);
  }
  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::DENSE_QR;
  solver_options.max_num_iterations = 200;
  solver_options.function_tolerance = 1e-16;
  solver_options.gradient_tolerance = 1e-16;
  solver_options.parameter_tolerance = 1e-16;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);

  KannalaBrandtFit fit{Camera(CameraModelId::kKannalaBrandt, source.Width(), source.Height(),
                              std::vector<double>(params, params + 8))};
  double sum_squared = 0;
  for (std::size_t i = 0; i < directions.size(); ++i) {
    Eigen::Vector2d pixel;
    fit.camera.Project(directions[i], &pixel);
    const double error = (pixel - pixels[i]).norm();
    sum_squared += error * error;
    fit.max_px = std::max(fit.max_px, error);
  }
  fit.num_samples = static_cast<int>(directions.size());
  fit.rms_px = std::sqrt(sum_squared / fit.num_samples);
  return fit;
}

}  // namespace pipescope
