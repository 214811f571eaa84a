#include "pipescope/camera/calibration.h"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <regex>

#include "pipescope/util/error.h"
#include "pipescope/util/median.h"

namespace pipescope {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

cv::Mat ToGrey8(const cv::Mat& image) {
  cv::Mat grey = image;
  if (image.channels() == 3) cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  if (image.channels() == 4) cv::cvtColor(image, grey, cv::COLOR_BGRA2GRAY);
  if (grey.depth() == CV_8U) return grey;
  cv::Mat grey8;
  const double scale = grey.depth() == CV_16U ? 255.0 / 65535.0 : 1.0;
  grey.convertTo(grey8, CV_8U, scale);
  return grey8;
}

// How far each corner is from the nearest edge of the pattern that does not pass through it
// (px): in each of the up to four squares of the inner grid that meet at the corner, spanned by
// the vectors a and b to its neighbours, the far edges lie at |a x b| / |a| and |a x b| / |b|.
// Under strong perspective or fisheye compression the squares shear, and this is much less
// than the spacing of the corners.
std::vector<double> CornerClearances(const std::vector<Eigen::Vector2d>& corners,
                                     const CheckerboardSpec& board) {
  std::vector<double> clearances(corners.size(), std::numeric_limits<double>::infinity());
  for (int r = 0; r < board.rows; ++r) {
    for (int c = 0; c < board.cols; ++c) {
      const Eigen::Vector2d& corner = corners[r * board.cols + c];
      for (const int dc : {-1, 1}) {
        for (const int dr : {-1, 1}) {
          if (c + dc < 0 || c + dc >= board.cols || r + dr < 0 || r + dr >= board.rows) continue;
          const Eigen::Vector2d a = corners[r * board.cols + c + dc] - corner;
          const Eigen::Vector2d b = corners[(r + dr) * board.cols + c] - corner;
          const double area = std::abs(a.x() * b.y() - a.y() * b.x());
          clearances[r * board.cols + c] =
              std::min({clearances[r * board.cols + c], area / a.norm(), area / b.norm()});
        }
      }
    }
  }
  return clearances;
}

// Smoothing of the image before its gradient is taken (px): with the gradient band-limited, its
// samples on the pixel grid stand for the continuous field and the refinement has no
// preference for any sub-pixel position.
constexpr double kGradientSigmaPx = 1.0;
constexpr int kMaxRefinementIterations = 50;
constexpr double kWindowClearanceFraction = 0.7;
constexpr double kMinWindowSigmaPx = 0.8;

// Sub-pixel corner refinement by the gradient-orthogonality condition of Förstner, the one
// cv::cornerSubPix solves: along the edges through a corner q the image gradient g(p) is
// perpendicular to p - q, so q minimises sum_p w(p - q) (g(p)^T (p - q))^2 and, for fixed
// weights, solves [sum w g g^T] q = sum w g g^T p. Unlike cv::cornerSubPix, which resamples the
// image around the current estimate by bilinear interpolation and so pulls corners towards
// pixel boundaries by up to 0.06 px on sharp images, the gradient here is a Gaussian derivative
// sampled on the pixel grid and only the Gaussian window w moves with q; the fixed point is
// iterated. The window reaches (3 sigma) kWindowClearanceFraction of the corner's clearance, so
// only the two edges through the corner fall in it; a corner that wanders off by more than
// half its clearance was not a clean X junction and keeps the detector's estimate.
void RefineCornerPositions(const cv::Mat& grey8, const std::vector<double>& clearances,
                           std::vector<Eigen::Vector2d>* corners) {
  cv::Mat image, smooth, gx, gy;
  grey8.convertTo(image, CV_32F);
  cv::GaussianBlur(image, smooth, cv::Size(0, 0), kGradientSigmaPx);
  cv::Sobel(smooth, gx, CV_32F, 1, 0, 3, 1.0 / 8.0);
  cv::Sobel(smooth, gy, CV_32F, 0, 1, 3, 1.0 / 8.0);
  for (std::size_t k = 0; k < corners->size(); ++k) {
    Eigen::Vector2d& corner = (*corners)[k];
    const double window_sigma =
        std::max(kMinWindowSigmaPx, kWindowClearanceFraction * clearances[k] / 3.0);
    const double radius = 3.0 * window_sigma;
    const double inverse_two_sigma2 = 1.0 / (2.0 * window_sigma * window_sigma);
    Eigen::Vector2d q = corner;
    for (int iteration = 0; iteration < kMaxRefinementIterations; ++iteration) {
      Eigen::Matrix2d a = Eigen::Matrix2d::Zero();
      Eigen::Vector2d b = Eigen::Vector2d::Zero();
      const int x0 = std::max(1, static_cast<int>(std::ceil(q.x() - radius)));
      const int x1 = std::min(image.cols - 2, static_cast<int>(std::floor(q.x() + radius)));
      const int y0 = std::max(1, static_cast<int>(std::ceil(q.y() - radius)));
      const int y1 = std::min(image.rows - 2, static_cast<int>(std::floor(q.y() + radius)));
      for (int y = y0; y <= y1; ++y) {
        const float* row_x = gx.ptr<float>(y);
        const float* row_y = gy.ptr<float>(y);
        for (int x = x0; x <= x1; ++x) {
          const Eigen::Vector2d p(x, y);
          const double d2 = (p - q).squaredNorm();
          if (d2 > radius * radius) continue;
          const Eigen::Vector2d g(row_x[x], row_y[x]);
          const Eigen::Matrix2d weighted = std::exp(-d2 * inverse_two_sigma2) * g * g.transpose();
          a += weighted;
          b += weighted * p;
        }
      }
      if (!(std::abs(a.determinant()) > 1e-12 * a.squaredNorm())) break;
      const Eigen::Vector2d next = a.inverse() * b;
      if (!next.allFinite()) break;
      const double step = (next - q).norm();
      q = next;
      if (step < 1e-4) break;
    }
    if ((q - corner).norm() <= 0.5 * clearances[k]) corner = q;
  }
}

Eigen::Isometry3d PoseFromAngleAxis(const double* pose) {
  const Eigen::Vector3d angle_axis(pose[0], pose[1], pose[2]);
  Eigen::Isometry3d cam_from_board = Eigen::Isometry3d::Identity();
  const double angle = angle_axis.norm();
  if (angle > 0.0) {
    cam_from_board.linear() = Eigen::AngleAxisd(angle, angle_axis / angle).toRotationMatrix();
  }
  cam_from_board.translation() = Eigen::Vector3d(pose[3], pose[4], pose[5]);
  return cam_from_board;
}

std::array<double, 6> AngleAxisFromPose(const Eigen::Isometry3d& cam_from_board) {
  const Eigen::AngleAxisd rotation(cam_from_board.rotation());
  const Eigen::Vector3d angle_axis = rotation.angle() * rotation.axis();
  const Eigen::Vector3d& t = cam_from_board.translation();
  return {angle_axis.x(), angle_axis.y(), angle_axis.z(), t.x(), t.y(), t.z()};
}

// The reprojection error of one board corner, the term summed in 001 §II:
//   e = pi(params, R(w) X + t) - u,
// with pi the model's projection (camera_models.h; 001 eq. 1 for fisheye-poly), X the corner in
// the board frame, (w, t) the board's pose as angle-axis and translation, u the detected corner.
// The projection is templated, so Ceres differentiates it exactly with Jets.
template <typename Model>
struct BoardCornerError {
  BoardCornerError(const Eigen::Vector3d& point_board, const Eigen::Vector2d& observed)
      : point_board_(point_board), observed_(observed) {}

  template <typename T>
  bool operator()(const T* params, const T* cam_from_board, T* residuals) const {
    const T point[3] = {T(point_board_.x()), T(point_board_.y()), T(point_board_.z())};
    T point_cam[3];
    ceres::AngleAxisRotatePoint(cam_from_board, point, point_cam);
    for (int i = 0; i < 3; ++i) point_cam[i] += cam_from_board[3 + i];
    T pixel[2];
    Model::ProjectPoint(params, point_cam, pixel);
    residuals[0] = pixel[0] - observed_.x();
    residuals[1] = pixel[1] - observed_.y();
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Vector3d& point_board,
                                     const Eigen::Vector2d& observed) {
    return new ceres::AutoDiffCostFunction<BoardCornerError, 2, Model::kNumParams, 6>(
        new BoardCornerError(point_board, observed));
  }

  Eigen::Vector3d point_board_;
  Eigen::Vector2d observed_;
};

// Minimises the sum of squared corner reprojection errors over the parameters (except
// `fixed_params`) and all board poses, with Levenberg-Marquardt. Returns Ceres' verdict.
bool RefineCalibration(CameraModelId model_id, const CheckerboardSpec& board,
                       const std::vector<CalibrationView>& views,
                       const std::vector<int>& fixed_params, int max_iterations,
                       std::vector<double>* params, std::vector<std::array<double, 6>>* poses) {
  const std::vector<Eigen::Vector3d> points_board = CheckerboardCorners(board);
  ceres::Problem problem;
  for (std::size_t v = 0; v < views.size(); ++v) {
    for (std::size_t j = 0; j < points_board.size(); ++j) {
      ceres::CostFunction* cost = VisitCameraModel(model_id, [&](auto model) {
        return BoardCornerError<decltype(model)>::Create(points_board[j], views[v].corners[j]);
      });
      problem.AddResidualBlock(cost, nullptr, params->data(), (*poses)[v].data());
    }
  }
  if (!fixed_params.empty()) {
    problem.SetManifold(params->data(),
                        new ceres::SubsetManifold(static_cast<int>(params->size()), fixed_params));
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_SCHUR;
  options.max_num_iterations = max_iterations;
  options.function_tolerance = 1e-14;
  options.gradient_tolerance = 1e-14;
  options.parameter_tolerance = 1e-14;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  return summary.IsSolutionUsable();
}

// Bearing of a pixel under an equidistant lens, r = k1 theta about `centre`; false past 180
// degrees.
bool EquidistantBearing(const Eigen::Vector2d& pixel, const Eigen::Vector2d& centre, double k1,
                        Eigen::Vector3d* bearing) {
  const Eigen::Vector2d offset = pixel - centre;
  const double r = offset.norm();
  const double theta = r / k1;
  if (theta >= M_PI - 1e-3) return false;
  if (r == 0.0) {
    *bearing = Eigen::Vector3d::UnitZ();
    return true;
  }
  const double sin_theta = std::sin(theta);
  *bearing =
      Eigen::Vector3d(sin_theta * offset.x() / r, sin_theta * offset.y() / r, std::cos(theta));
  return true;
}

// Initial guess shared by the fisheye fits: an equidistant lens r = k1 theta centred on the
// image (the design target of most fisheye lenses, and exact for fisheye-poly's and
// Kannala-Brandt's first term). For a trial k1 every corner is unprojected onto the view sphere,
// each board's pose follows from PlanarPoseFromBearings, and the median reprojection error of
// all corners scores the trial; a log-spaced sweep and a golden-section search find the best
// k1. Nothing in it assumes the corners lie in front of the image plane, so it holds past 180
// degrees.
struct EquidistantGuess {
  double k1 = 0.0;
  std::vector<Eigen::Isometry3d> cam_from_board;
  double median_error_px = std::numeric_limits<double>::infinity();
};

EquidistantGuess EvaluateEquidistant(double k1, const Eigen::Vector2d& centre,
                                     const CheckerboardSpec& board,
                                     const std::vector<CalibrationView>& views) {
  EquidistantGuess guess;
  guess.k1 = k1;
  const std::vector<Eigen::Vector3d> points_board = CheckerboardCorners(board);
  const double params[6] = {k1, 0.0, 0.0, 0.0, centre.x(), centre.y()};
  std::vector<double> errors;
  for (const CalibrationView& view : views) {
    std::vector<Eigen::Vector3d> bearings(view.corners.size());
    for (std::size_t j = 0; j < view.corners.size(); ++j) {
      if (!EquidistantBearing(view.corners[j], centre, k1, &bearings[j])) return guess;
    }
    Eigen::Isometry3d cam_from_board;
    if (!PlanarPoseFromBearings(points_board, bearings, &cam_from_board)) return guess;
    for (std::size_t j = 0; j < points_board.size(); ++j) {
      const Eigen::Vector3d point_cam = cam_from_board * points_board[j];
      Eigen::Vector2d pixel;
      FisheyePolyModel::ProjectPoint(params, point_cam.data(), pixel.data());
      errors.push_back((pixel - view.corners[j]).norm());
    }
    guess.cam_from_board.push_back(cam_from_board);
  }
  if (!errors.empty()) guess.median_error_px = UpperMedian(std::move(errors));
  return guess;
}

EquidistantGuess GuessEquidistant(int width, int height, const CheckerboardSpec& board,
                                  const std::vector<CalibrationView>& views, int samples) {
  const Eigen::Vector2d centre(0.5 * (width - 1), 0.5 * (height - 1));
  // From a 300-degree circle filling a fifth of the short side up to a 10-degree lens across
  // the long side: every lens a board calibration meets.
  const double k_min = 0.1 * std::min(width, height) / (5.0 * M_PI / 3.0);
  const double k_max = 0.5 * std::max(width, height) / (5.0 * M_PI / 180.0);
  const double log_step = std::log(k_max / k_min) / (samples - 1);
  int best = -1;
  double best_error = std::numeric_limits<double>::infinity();
  for (int i = 0; i < samples; ++i) {
    const double error =
        EvaluateEquidistant(k_min * std::exp(i * log_step), centre, board, views).median_error_px;
    if (error < best_error) {
      best_error = error;
      best = i;
    }
  }
  if (best < 0) return {};
  // Golden-section search on log k1 between the best sample's neighbours.
  const double golden = 0.5 * (std::sqrt(5.0) - 1.0);
  double a = std::log(k_min) + (best - 1) * log_step;
  double b = std::log(k_min) + (best + 1) * log_step;
  auto cost = [&](double log_k) {
    return EvaluateEquidistant(std::exp(log_k), centre, board, views).median_error_px;
  };
  double c = b - golden * (b - a);
  double d = a + golden * (b - a);
  double cost_c = cost(c);
  double cost_d = cost(d);
  for (int iteration = 0; iteration < 40; ++iteration) {
    if (cost_c < cost_d) {
      b = d;
      d = c;
      cost_d = cost_c;
      c = b - golden * (b - a);
      cost_c = cost(c);
    } else {
      a = c;
      c = d;
      cost_c = cost_d;
      d = a + golden * (b - a);
      cost_d = cost(d);
    }
  }
  EquidistantGuess refined = EvaluateEquidistant(std::exp(0.5 * (a + b)), centre, board, views);
  if (refined.median_error_px <= best_error) return refined;
  return EvaluateEquidistant(k_min * std::exp(best * log_step), centre, board, views);
}

std::vector<std::vector<cv::Point3f>> ObjectPointsCv(const CheckerboardSpec& board, size_t views) {
  std::vector<cv::Point3f> points;
  for (const Eigen::Vector3d& point : CheckerboardCorners(board)) {
    points.emplace_back(static_cast<float>(point.x()), static_cast<float>(point.y()), 0.0f);
  }
  return std::vector<std::vector<cv::Point3f>>(views, points);
}

std::vector<std::vector<cv::Point2f>> ImagePointsCv(const std::vector<CalibrationView>& views) {
  std::vector<std::vector<cv::Point2f>> image_points;
  for (const CalibrationView& view : views) {
    std::vector<cv::Point2f>& points = image_points.emplace_back();
    for (const Eigen::Vector2d& corner : view.corners) {
      points.emplace_back(static_cast<float>(corner.x()), static_cast<float>(corner.y()));
    }
  }
  return image_points;
}

Eigen::Isometry3d PoseFromCv(const cv::Mat& rvec, const cv::Mat& tvec) {
  cv::Mat r64, t64;
  rvec.convertTo(r64, CV_64F);
  tvec.convertTo(t64, CV_64F);
  const double pose[6] = {r64.at<double>(0), r64.at<double>(1), r64.at<double>(2),
                          t64.at<double>(0), t64.at<double>(1), t64.at<double>(2)};
  return PoseFromAngleAxis(pose);
}

// Largest angle of a corner from the optical axis under the fitted poses.
double MaxCornerAngleDeg(const CheckerboardSpec& board,
                         const std::vector<Eigen::Isometry3d>& cam_from_board) {
  double max_angle = 0.0;
  for (const Eigen::Isometry3d& pose : cam_from_board) {
    for (const Eigen::Vector3d& point : CheckerboardCorners(board)) {
      const Eigen::Vector3d p = pose * point;
      max_angle = std::max(max_angle, std::atan2(p.head<2>().norm(), p.z()));
    }
  }
  return max_angle * kRadToDeg;
}

// OpenCV's Zhang calibration with the five-coefficient distortion model, k3 held at 0 unless
// the corners reach options.radtan_k3_min_angle_deg from the axis.
CalibrationResult CalibratePinholeRadtan(int width, int height, const CheckerboardSpec& board,
                                         const std::vector<CalibrationView>& views,
                                         const CalibrationOptions& options) {
  const auto object_points = ObjectPointsCv(board, views.size());
  const auto image_points = ImagePointsCv(views);
  const cv::TermCriteria criteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS,
                                  options.max_iterations, 1e-12);
  cv::Mat camera_matrix, distortion;
  std::vector<cv::Mat> rvecs, tvecs;
  cv::calibrateCamera(object_points, image_points, cv::Size(width, height), camera_matrix,
                      distortion, rvecs, tvecs, cv::CALIB_FIX_K3, criteria);
  std::vector<Eigen::Isometry3d> poses;
  for (std::size_t v = 0; v < views.size(); ++v) poses.push_back(PoseFromCv(rvecs[v], tvecs[v]));
  bool k3_free = false;
  if (MaxCornerAngleDeg(board, poses) >= options.radtan_k3_min_angle_deg) {
    k3_free = true;
    cv::calibrateCamera(object_points, image_points, cv::Size(width, height), camera_matrix,
                        distortion, rvecs, tvecs, cv::CALIB_USE_INTRINSIC_GUESS, criteria);
    poses.clear();
    for (std::size_t v = 0; v < views.size(); ++v) poses.push_back(PoseFromCv(rvecs[v], tvecs[v]));
  }
  cv::Mat k, d;
  camera_matrix.convertTo(k, CV_64F);
  distortion.reshape(1, 1).convertTo(d, CV_64F);
  const std::vector<double> params = {k.at<double>(0, 0), k.at<double>(1, 1), k.at<double>(0, 2),
                                      k.at<double>(1, 2), d.at<double>(0),    d.at<double>(1),
                                      d.at<double>(2),    d.at<double>(3),    d.at<double>(4)};
  CalibrationResult result(Camera(CameraModelId::kPinholeRadtan, width, height, params));
  result.cam_from_board = std::move(poses);
  char method[160];
  std::snprintf(method, sizeof(method), "cv::calibrateCamera, k1 k2 p1 p2 %s%g%s",
                k3_free ? "k3 (corners beyond " : "(k3 = 0: corners within ",
                options.radtan_k3_min_angle_deg, " deg of the axis)");
  result.method = method;
  return result;
}

// OpenCV's fisheye calibration, started from the equidistant guess: its own start, a focal
// length of max(width, height) / pi, is far off for anything but a 180-degree lens.
CalibrationResult CalibrateKannalaBrandt(int width, int height, const CheckerboardSpec& board,
                                         const std::vector<CalibrationView>& views,
                                         const CalibrationOptions& options) {
  const EquidistantGuess guess =
      GuessEquidistant(width, height, board, views, options.fisheye_k1_samples);
  if (guess.cam_from_board.empty()) {
    throw InputError("kannala-brandt: no equidistant lens explains the corners");
  }
  std::vector<std::vector<cv::Point3d>> object_points;
  std::vector<std::vector<cv::Point2d>> image_points;
  for (const CalibrationView& view : views) {
    std::vector<cv::Point3d>& object = object_points.emplace_back();
    for (const Eigen::Vector3d& point : CheckerboardCorners(board)) {
      object.emplace_back(point.x(), point.y(), point.z());
    }
    std::vector<cv::Point2d>& image = image_points.emplace_back();
    for (const Eigen::Vector2d& corner : view.corners) image.emplace_back(corner.x(), corner.y());
  }
  cv::Matx33d camera_matrix(guess.k1, 0.0, 0.5 * (width - 1), 0.0, guess.k1, 0.5 * (height - 1),
                            0.0, 0.0, 1.0);
  cv::Vec4d distortion(0.0, 0.0, 0.0, 0.0);
  std::vector<cv::Vec3d> rvecs, tvecs;
  const cv::TermCriteria criteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS,
                                  options.max_iterations, 1e-12);
  cv::fisheye::calibrate(object_points, image_points, cv::Size(width, height), camera_matrix,
                         distortion, rvecs, tvecs,
                         cv::fisheye::CALIB_USE_INTRINSIC_GUESS |
                             cv::fisheye::CALIB_RECOMPUTE_EXTRINSIC | cv::fisheye::CALIB_FIX_SKEW,
                         criteria);
  const std::vector<double> params = {camera_matrix(0, 0), camera_matrix(1, 1), camera_matrix(0, 2),
                                      camera_matrix(1, 2), distortion[0],       distortion[1],
                                      distortion[2],       distortion[3]};
  CalibrationResult result(Camera(CameraModelId::kKannalaBrandt, width, height, params));
  for (std::size_t v = 0; v < views.size(); ++v) {
    const double pose[6] = {rvecs[v][0], rvecs[v][1], rvecs[v][2],
                            tvecs[v][0], tvecs[v][1], tvecs[v][2]};
    result.cam_from_board.push_back(PoseFromAngleAxis(pose));
  }
  result.method = "cv::fisheye::calibrate from an equidistant guess";
  return result;
}

// 001 §II: Ceres fit of eq. 1 in two stages from the equidistant guess, first k1 and the
// principal point (the higher terms at 0, so a poor start cannot bend the polynomial), then all
// six parameters.
CalibrationResult CalibrateFisheyePoly(int width, int height, const CheckerboardSpec& board,
                                       const std::vector<CalibrationView>& views,
                                       const CalibrationOptions& options) {
  const EquidistantGuess guess =
      GuessEquidistant(width, height, board, views, options.fisheye_k1_samples);
  if (guess.cam_from_board.empty()) {
    throw InputError("fisheye-poly: no equidistant lens explains the corners");
  }
  std::vector<double> params = {guess.k1, 0.0, 0.0, 0.0, 0.5 * (width - 1), 0.5 * (height - 1)};
  std::vector<std::array<double, 6>> poses;
  for (const Eigen::Isometry3d& pose : guess.cam_from_board) {
    poses.push_back(AngleAxisFromPose(pose));
  }
  if (!RefineCalibration(CameraModelId::kFisheyePoly, board, views, {1, 2, 3},
                         options.max_iterations, &params, &poses) ||
      !RefineCalibration(CameraModelId::kFisheyePoly, board, views, {}, options.max_iterations,
                         &params, &poses)) {
    throw InputError("fisheye-poly: the non-linear fit failed");
  }
  CalibrationResult result(Camera(CameraModelId::kFisheyePoly, width, height, params));
  for (const auto& pose : poses) result.cam_from_board.push_back(PoseFromAngleAxis(pose.data()));
  result.method = "Ceres Levenberg-Marquardt of 001 eq. 1 from an equidistant guess";
  return result;
}

}  // namespace

CheckerboardSpec ParseCheckerboardSize(const std::string& text, const std::string& flag) {
  static const std::regex pattern(R"(\s*(\d+)\s*[xX]\s*(\d+)\s*)");
  std::smatch match;
  if (!std::regex_match(text, match, pattern)) {
    throw InputError(flag + " " + text + ": expected COLSxROWS inner corners, e.g. 9x6");
  }
  CheckerboardSpec board;
  board.cols = std::stoi(match[1]);
  board.rows = std::stoi(match[2]);
  if (board.cols < 2 || board.rows < 2) {
    throw InputError(flag + " " + text + ": a board needs at least 2x2 inner corners");
  }
  return board;
}

std::vector<Eigen::Vector3d> CheckerboardCorners(const CheckerboardSpec& board) {
  std::vector<Eigen::Vector3d> corners;
  corners.reserve(board.NumCorners());
  for (int r = 0; r < board.rows; ++r) {
    for (int c = 0; c < board.cols; ++c) {
      corners.emplace_back(c * board.square_m, r * board.square_m, 0.0);
    }
  }
  return corners;
}

bool DetectCheckerboardCorners(const cv::Mat& image, const CheckerboardSpec& board,
                               std::vector<Eigen::Vector2d>* corners) {
  const cv::Mat grey = ToGrey8(image);
  std::vector<cv::Point2f> points;
  // Without CALIB_CB_EXHAUSTIVE, which can take half a minute on an image without a board; the
  // classic cv::findChessboardCorners finds fewer boards on distorted images and is slower on
  // noisy ones.
  if (!cv::findChessboardCornersSB(grey, cv::Size(board.cols, board.rows), points,
                                   cv::CALIB_CB_NORMALIZE_IMAGE) ||
      static_cast<int>(points.size()) != board.NumCorners()) {
    return false;
  }
  corners->clear();
  for (const cv::Point2f& point : points) corners->emplace_back(point.x, point.y);
  RefineCornerPositions(grey, CornerClearances(*corners, board), corners);
  return true;
}

std::vector<double> CornerReprojectionErrors(const Camera& camera,
                                             const Eigen::Isometry3d& cam_from_board,
                                             const CheckerboardSpec& board,
                                             const std::vector<Eigen::Vector2d>& corners) {
  const std::vector<Eigen::Vector3d> points_board = CheckerboardCorners(board);
  std::vector<double> errors;
  for (std::size_t j = 0; j < points_board.size() && j < corners.size(); ++j) {
    Eigen::Vector2d pixel;
    const ProjectionStatus status = camera.Project(cam_from_board * points_board[j], &pixel);
    errors.push_back(status == ProjectionStatus::kBehindCamera
                         ? std::numeric_limits<double>::infinity()
                         : (pixel - corners[j]).norm());
  }
  return errors;
}

bool PlanarPoseFromBearings(const std::vector<Eigen::Vector3d>& points_board,
                            const std::vector<Eigen::Vector3d>& bearings,
                            Eigen::Isometry3d* cam_from_board) {
  const int n = static_cast<int>(points_board.size());
  if (n < 4 || bearings.size() != points_board.size()) return false;
  // Hartley's normalisation of the board coordinates: centroid at the origin, mean distance
  // sqrt(2), so the linear system is well conditioned whatever the square size.
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const Eigen::Vector3d& point : points_board) mean += point.head<2>();
  mean /= n;
  double mean_distance = 0.0;
  for (const Eigen::Vector3d& point : points_board)
    mean_distance += (point.head<2>() - mean).norm();
  mean_distance /= n;
  if (!(mean_distance > 0.0)) return false;
  const double scale = std::sqrt(2.0) / mean_distance;
  Eigen::Matrix3d normalise;
  normalise << scale, 0.0, -scale * mean.x(), 0.0, scale, -scale * mean.y(), 0.0, 0.0, 1.0;

  // b x (H q) = 0 for the rows h1, h2, h3 of H, three equations (two independent) per point.
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(3 * n, 9);
  for (int j = 0; j < n; ++j) {
    const Eigen::Vector3d q =
        normalise * Eigen::Vector3d(points_board[j].x(), points_board[j].y(), 1.0);
    const Eigen::Vector3d& b = bearings[j];
    a.block<1, 3>(3 * j, 3) = -b.z() * q.transpose();
    a.block<1, 3>(3 * j, 6) = b.y() * q.transpose();
    a.block<1, 3>(3 * j + 1, 0) = b.z() * q.transpose();
    a.block<1, 3>(3 * j + 1, 6) = -b.x() * q.transpose();
    a.block<1, 3>(3 * j + 2, 0) = -b.y() * q.transpose();
    a.block<1, 3>(3 * j + 2, 3) = b.x() * q.transpose();
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeFullV);
  const Eigen::Matrix<double, 9, 1> h = svd.matrixV().col(8);
  Eigen::Matrix3d homography;
  homography << h(0), h(1), h(2), h(3), h(4), h(5), h(6), h(7), h(8);
  homography = homography * normalise;
  // H (X, Y, 1) = lambda (R X + t) with lambda > 0: the points lie along their bearings, not
  // opposite them.
  double along = 0.0;
  for (int j = 0; j < n; ++j) {
    along += bearings[j].dot(homography *
                             Eigen::Vector3d(points_board[j].x(), points_board[j].y(), 1.0));
  }
  if (along < 0.0) homography = -homography;
  const double lambda = 0.5 * (homography.col(0).norm() + homography.col(1).norm());
  if (!(lambda > 0.0) || !std::isfinite(lambda)) return false;
  Eigen::Matrix3d rotation;
  rotation.col(0) = homography.col(0) / lambda;
  rotation.col(1) = homography.col(1) / lambda;
  rotation.col(2) = rotation.col(0).cross(rotation.col(1));
  const Eigen::JacobiSVD<Eigen::Matrix3d> nearest(rotation,
                                                  Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d fix = Eigen::Matrix3d::Identity();
  fix(2, 2) = (nearest.matrixU() * nearest.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
  cam_from_board->setIdentity();
  cam_from_board->linear() = nearest.matrixU() * fix * nearest.matrixV().transpose();
  cam_from_board->translation() = homography.col(2) / lambda;
  return true;
}

CalibrationResult CalibrateCamera(CameraModelId model_id, int width, int height,
                                  const CheckerboardSpec& board,
                                  const std::vector<CalibrationView>& views,
                                  const CalibrationOptions& options) {
  if (views.empty()) throw InputError("calibration needs at least one view of the board");
  for (const CalibrationView& view : views) {
    if (static_cast<int>(view.corners.size()) != board.NumCorners()) {
      throw InputError(view.name + ": " + std::to_string(view.corners.size()) +
                       " corners, the board has " + std::to_string(board.NumCorners()));
    }
  }
  CalibrationResult result = [&] {
    // OpenCV refuses degenerate view sets (too few views, ill-conditioned fits) by throwing;
    // that is bad input, not a bug.
    try {
      switch (model_id) {
        case CameraModelId::kPinholeRadtan:
          return CalibratePinholeRadtan(width, height, board, views, options);
        case CameraModelId::kKannalaBrandt:
          return CalibrateKannalaBrandt(width, height, board, views, options);
        case CameraModelId::kFisheyePoly:
          return CalibrateFisheyePoly(width, height, board, views, options);
      }
    } catch (const cv::Exception& error) {
      throw InputError(CameraModelName(model_id) + ": the OpenCV fit failed on these " +
                       std::to_string(views.size()) + " views: " + error.what());
    }
    throw std::invalid_argument("invalid CameraModelId");
  }();

  double sum_squares = 0.0;
  for (std::size_t v = 0; v < views.size(); ++v) {
    double view_sum = 0.0;
    for (double error : CornerReprojectionErrors(result.camera, result.cam_from_board[v], board,
                                                 views[v].corners)) {
      view_sum += error * error;
    }
    result.view_rms_px.push_back(std::sqrt(view_sum / board.NumCorners()));
    sum_squares += view_sum;
  }
  result.num_corners = static_cast<int>(views.size()) * board.NumCorners();
  result.rms_px = std::sqrt(sum_squares / result.num_corners);
  result.max_angle_deg = MaxCornerAngleDeg(board, result.cam_from_board);
  if (!std::isfinite(result.rms_px)) {
    throw InputError(result.camera.ModelName() +
                     ": the fit left corners that do not project; check --board and the images");
  }
  return result;
}

}  // namespace pipescope
