#include "pipescope/estimation/cross_section_alignment.h"

#include <ceres/ceres.h>
#include <ceres/cubic_interpolation.h>

#include <opencv2/imgproc.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include "pipescope/dense/local_contrast.h"
#include "pipescope/dense/unrolled_wall_registration.h"
#include "pipescope/estimation/least_squares_solve.h"
#include "pipescope/geometry/pipe_cylinder.h"
#include "pipescope/camera/camera_models.h"
#include "pipescope/util/error.h"

namespace pipescope {
namespace {

using Interpolator = ceres::BiCubicInterpolator<ceres::Grid2D<float, 1>>;

// The parameters: travel, roll, offset X, offset Y.
constexpr int kParameters = 4;

double Scalar(double value) { return value; }
template <typename T, int N>
double Scalar(const ceres::Jet<T, N>& value) {
  return value.a;
}

// One sampled key-frame pixel: the current frame's grey level where the wall point it sees
// lands, less the key's, over the residuals' spread. The parameters: travel, roll, offset X,
// offset Y. The key camera, moved across the pipe by the offset, casts the pixel's ray onto the
// wall (geometry/RayToWall's closed form); the current camera is the moved key camera rolled
// about the axis and moved along it (dense/unrolled_wall_registration.h, PipeAxisMotion). A
// point that leaves the frame contributes nothing (the samples were chosen well inside it).
struct PhotometricResidual {
  CameraModelId model;
  const double* camera_params;
  const Interpolator* current;
  Eigen::Matrix3d cam_from_world;  // the key camera's rotation, inverted
  Eigen::Vector3d key_position;
  Eigen::Vector3d direction;  // the pixel's ray in the pipe frame
  double grey;
  double radius;
  double inverse_sigma;
  int downsample;
  cv::Size size;

  template <typename T>
  bool operator()(const T* p, T* residual) const {
    residual[0] = T(0.0);
    const T cx = key_position.x() + p[2], cy = key_position.y() + p[3];
    const double a = direction.head<2>().squaredNorm();
    const T b = cx * direction.x() + cy * direction.y();
    const T c = cx * cx + cy * cy - radius * radius;
    const T discriminant = b * b - a * c;
    if (!(Scalar(discriminant) > 0.0)) return true;
    const T depth = (-b + sqrt(discriminant)) / a;
    // The wall point relative to the moved key camera, turned back by the roll: the current
    // camera sees it at cam_from_world * (Rz(-roll) P - c - travel z).
    const T px = cx + depth * direction.x(), py = cy + depth * direction.y();
    const T cos_roll = cos(p[1]), sin_roll = sin(p[1]);
    const T unrolled[3] = {cos_roll * px + sin_roll * py - cx,
                           -sin_roll * px + cos_roll * py - cy,
                           depth * direction.z() - p[0]};
    T point_cam[3];
    for (int row = 0; row < 3; ++row) {
      point_cam[row] = cam_from_world(row, 0) * unrolled[0] + cam_from_world(row, 1) * unrolled[1] +
                       cam_from_world(row, 2) * unrolled[2];
    }
    if (!(Scalar(point_cam[2]) > 0.0)) return true;
    T params[kMaxNumCameraParams];
    for (int k = 0; k < kMaxNumCameraParams; ++k) params[k] = T(camera_params[k]);
    T pixel[2];
    ProjectPoint(model, params, point_cam, pixel);
    // Full-resolution pixel x lies at (x + 0.5) / factor - 0.5 in the box-filtered frame.
    const T x = (pixel[0] + 0.5) / double(downsample) - 0.5;
    const T y = (pixel[1] + 0.5) / double(downsample) - 0.5;
    if (Scalar(x) < 1.0 || Scalar(y) < 1.0 || Scalar(x) > size.width - 2.0 ||
        Scalar(y) > size.height - 2.0) {
      return true;
    }
    T value;
    current->Evaluate(y, x, &value);
    residual[0] = (value - grey) * inverse_sigma;
    return true;
  }
};

// The crawler's place across the pipe changes little over one key-frame step: the offset is
// held to where the last key frame put it with this standard deviation (a Kalman filter's
// prediction of a random walk).
struct OffsetPrior {
  Eigen::Vector2d expected;
  double inverse_sigma;
  template <typename T>
  bool operator()(const T* p, T* residual) const {
    residual[0] = (p[2] - expected.x()) * inverse_sigma;
    residual[1] = (p[3] - expected.y()) * inverse_sigma;
    return true;
  }
};

struct SolutionSpread {
  double residual_sigma = 0.0;  // 1.4826 MAD of the residuals, in their units before scaling
  double offset_sigma_m = 0.0;
};

// At the solution, from one evaluation of the photometric residuals (the prior left out):
// - their spread. Ceres returns them robustified; Huber's correction (Triggs et al., as Ceres'
//   Corrector applies it where rho'' <= 0) maps |r| > k to sqrt(k |r|), so |r| = r'^2 / k there.
// - what the frames alone fix of the offset: the larger standard deviation of its two
//   components from the residuals' Gauss-Newton information (robustly weighted), the travel and
//   roll marginalised. Infinite when it is not fixed at all.
SolutionSpread SpreadAtSolution(ceres::Problem* problem,
                                const std::vector<ceres::ResidualBlockId>& photometric,
                                double huber_k, double residual_scale) {
  ceres::Problem::EvaluateOptions evaluate;
  evaluate.residual_blocks = photometric;
  std::vector<double> residuals;
  ceres::CRSMatrix jacobian;
  problem->Evaluate(evaluate, nullptr, &residuals, nullptr, &jacobian);
  SolutionSpread spread;
  for (double& each : residuals) {
    each = std::abs(each);
    if (each > huber_k) each = each * each / huber_k;
  }
  std::nth_element(residuals.begin(), residuals.begin() + residuals.size() / 2, residuals.end());
  spread.residual_sigma = 1.4826 * residuals[residuals.size() / 2] * residual_scale;
  Eigen::Matrix4d information = Eigen::Matrix4d::Zero();
  for (int row = 0; row < jacobian.num_rows; ++row) {
    Eigen::Vector4d gradient = Eigen::Vector4d::Zero();
    for (int k = jacobian.rows[row]; k < jacobian.rows[row + 1]; ++k) {
      gradient(jacobian.cols[k]) = jacobian.values[k];
    }
    information += gradient * gradient.transpose();
  }
  const Eigen::FullPivLU<Eigen::Matrix4d> lu(information);
  if (!lu.isInvertible()) {
    spread.offset_sigma_m = std::numeric_limits<double>::infinity();
    return spread;
  }
  const Eigen::Matrix2d covariance = lu.inverse().bottomRightCorner<2, 2>();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(covariance);
  spread.offset_sigma_m = std::sqrt(std::max(eigen.eigenvalues().maxCoeff(), 0.0));
  return spread;
}

}  // namespace

CrossSectionAligner::CrossSectionAligner(const Camera& camera, double radius_m, int downsample,
                                         const CrossSectionAlignmentOptions& options)
    : camera_(camera), radius_m_(radius_m), downsample_(downsample), options_(options) {
  if (!(radius_m > 0.0)) throw InputError("cross-section alignment: the radius must be positive");
  if (downsample < 1 || options.stride_px < 1 || options.border_px < 0) {
    throw InputError("cross-section alignment: downsample and stride must be at least 1");
  }
}

cv::Mat CrossSectionAligner::Normalised(const cv::Mat& downsampled, double smooth_px) const {
  if (!(smooth_px > 0.0)) {
    return NormaliseLocalContrast(downsampled, options_.contrast_normalisation_px);
  }
  cv::Mat smoothed;
  cv::GaussianBlur(downsampled, smoothed, cv::Size(), smooth_px);
  return NormaliseLocalContrast(smoothed, options_.contrast_normalisation_px);
}

const std::vector<CrossSectionAligner::SamplePixel>& CrossSectionAligner::SamplePixels(
    const cv::Size& size) const {
  if (size == sample_size_) return sample_pixels_;
  sample_pixels_.clear();
  for (int y = options_.border_px; y < size.height - options_.border_px; y += options_.stride_px) {
    for (int x = options_.border_px; x < size.width - options_.border_px; x += options_.stride_px) {
      const Eigen::Vector2d full((x + 0.5) * downsample_ - 0.5, (y + 0.5) * downsample_ - 0.5);
      SamplePixel sample{x, y, Eigen::Vector3d::Zero()};
      if (camera_.Unproject(full, &sample.bearing)) sample_pixels_.push_back(sample);
    }
  }
  sample_size_ = size;
  return sample_pixels_;
}

CrossSectionAlignment CrossSectionAligner::Align(const cv::Mat& key, const cv::Mat& current,
                                                 const Eigen::Isometry3d& key_world_from_cam,
                                                 double travel_m, double roll_rad,
                                                 const Eigen::Vector2d& expected_offset_m) const {
  if (key.type() != CV_32F || current.type() != CV_32F || key.size() != current.size()) {
    throw InputError("cross-section alignment: the frames must be CV_32F and of one size");
  }
  const cv::Mat contiguous = current.isContinuous() ? current : current.clone();
  const ceres::Grid2D<float, 1> grid(contiguous.ptr<float>(), 0, contiguous.rows, 0,
                                     contiguous.cols);
  const Interpolator interpolator(grid);
  std::vector<double> camera_params(kMaxNumCameraParams, 0.0);
  std::copy(camera_.Params().begin(), camera_.Params().end(), camera_params.begin());
  double p[kParameters] = {travel_m, roll_rad, expected_offset_m.x(), expected_offset_m.y()};
  const double margin = options_.border_px;
  // Where the samples land at the start: the current camera at the expected place.
  Eigen::Isometry3d expected_key = key_world_from_cam;
  expected_key.translation().head<2>() += expected_offset_m;
  const Eigen::Isometry3d current_from_world =
      PipeAxisMotion(expected_key, travel_m, roll_rad).inverse();

  // The samples, and their residuals at the start.
  std::vector<PhotometricResidual> samples;
  std::vector<double> start_residuals;
  PhotometricResidual sample{camera_.ModelId(),
                             camera_params.data(),
                             &interpolator,
                             key_world_from_cam.linear().transpose(),
                             key_world_from_cam.translation(),
                             Eigen::Vector3d::Zero(),
                             0.0,
                             radius_m_,
                             1.0,
                             downsample_,
                             key.size()};
  for (const SamplePixel& pixel_ray : SamplePixels(key.size())) {
    sample.direction = key_world_from_cam.linear() * pixel_ray.bearing;
    sample.grey = key.at<float>(pixel_ray.y, pixel_ray.x);
    const std::optional<double> depth =
        RayToWall(key_world_from_cam.translation(), sample.direction, radius_m_);
    if (!depth) continue;
    Eigen::Vector2d pixel;
    const Eigen::Vector3d wall_point = key_world_from_cam.translation() + *depth * sample.direction;
    if (camera_.Project(current_from_world * wall_point, &pixel) ==
        ProjectionStatus::kBehindCamera) {
      continue;
    }
    const Eigen::Vector2d start = (pixel.array() + 0.5) / downsample_ - 0.5;
    if (start.x() < margin || start.y() < margin || start.x() > key.cols - 1 - margin ||
        start.y() > key.rows - 1 - margin) {
      continue;
    }
    double residual = 0.0;
    sample(p, &residual);
    samples.push_back(sample);
    start_residuals.push_back(std::abs(residual));
  }
  CrossSectionAlignment result;
  result.samples = static_cast<int>(samples.size());
  if (result.samples < 4 * kParameters) return result;
  // The residuals in units of their spread at the start (1.4826 MAD), so that the prior weighs
  // against what the frames can tell, whatever their texture and noise. (Their spread tile by
  // tile of the key frame, where the lights set the noise, did worse on every set-up tried.)
  std::nth_element(start_residuals.begin(), start_residuals.begin() + start_residuals.size() / 2,
                   start_residuals.end());
  const double sigma = std::max(1.4826 * start_residuals[start_residuals.size() / 2], 1e-6);

  // One loss for every sample: the problem does not own it, so it must outlive the problem.
  ceres::HuberLoss huber(options_.huber_sigmas);
  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  std::vector<ceres::ResidualBlockId> photometric;
  for (PhotometricResidual& each : samples) {
    each.inverse_sigma = 1.0 / sigma;
    photometric.push_back(problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<PhotometricResidual, 1, kParameters>(
            new PhotometricResidual(each)),
        &huber, p));
  }
  if (options_.offset_step_sigma_m > 0.0) {
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<OffsetPrior, 2, kParameters>(
                                 new OffsetPrior{expected_offset_m,
                                                 1.0 / options_.offset_step_sigma_m}),
                             nullptr, p);
  }
  const LeastSquaresOutcome outcome = SolveLeastSquares(
      &problem, ceres::DENSE_NORMAL_CHOLESKY, options_.max_iterations, /*observations=*/0);
  const SolutionSpread spread =
      SpreadAtSolution(&problem, photometric, options_.huber_sigmas, sigma);
  result.residual_sigma = spread.residual_sigma;
  result.too_faint = result.residual_sigma > options_.max_residual_sigma;
  result.offset_sigma_m = spread.offset_sigma_m;
  result.converged = outcome.usable;
  result.travel_m = p[0];
  result.roll_rad = p[1];
  result.offset_m = Eigen::Vector2d(p[2], p[3]);
  return result;
}

}  // namespace pipescope
