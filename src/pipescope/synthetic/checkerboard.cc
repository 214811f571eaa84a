#include "pipescope/synthetic/checkerboard.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

#include "pipescope/camera/camera_io.h"
#include "pipescope/io/trajectory.h"
#include "pipescope/synthetic/sensor.h"
#include "pipescope/synthetic/simulated_camera.h"
#include "pipescope/util/atomic_file.h"
#include "pipescope/util/error.h"
#include "pipescope/util/progress.h"
#include "pipescope/util/random.h"
#include "pipescope/util/staging_directory.h"
#include "pipescope/util/timer.h"

namespace pipescope {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

// Albedos: white paper, black toner, a grey room behind the board.
constexpr double kWhite = 1.0;
constexpr double kBlack = 0.05;
constexpr double kBackground = 0.25;
// Supersampling of pixels whose footprint crosses an edge, on a Hammersley point set: its 256
// samples have 256 distinct x and 256 distinct y coordinates, so even an edge along a pixel row
// or column is placed to 1/256 px (a regular 16 x 16 grid would place it to 1/16 px only, and
// the corner detector would inherit that error as a bias that depends on the sub-pixel phase).
constexpr int kSupersamples = 256;
// A slight defocus (Gaussian sigma, px): real lenses do not image a step as a step.
constexpr double kDefocusSigmaPx = 0.5;

// Pose sampling (GenerateCheckerboardPoses).
constexpr double kMaxTiltDeg = 50.0;
constexpr double kMaxSpinDeg = 30.0;
constexpr double kMaxFieldDeg = 110.0;
// Board size as a fraction of the field of view (its diagonal with the margin): smaller boards
// for the views aimed at the image's corners and edges, so they reach the rim (past 90 degrees
// on a wide fisheye) while their corners stay kMinCornerSpacingPx apart.
constexpr double kMinSizeFraction = 0.45;
constexpr double kMaxSizeFraction = 0.80;
constexpr double kMinRimSizeFraction = 0.18;
constexpr double kMaxRimSizeFraction = 0.30;
constexpr double kMaxIncidenceDeg = 75.0;
constexpr double kMinCornerSpacingPx = 6.0;
constexpr double kImageMarginPx = 3.0;
constexpr int kMaxPlacementAttempts = 300;

// Random streams of this writer (util/random.h), apart from the pipe simulator's.
constexpr std::uint64_t kBoardPoseStream = 201;
constexpr std::uint64_t kBoardNoiseStream = 202;

// Radiance of the board plane at board coordinates (x, y), head-on.
double BoardAlbedo(const CheckerboardSpec& board, double x, double y) {
  const double u = x / board.square_m;
  const double v = y / board.square_m;
  if (!(u >= -2.0 && u < board.cols + 1.0 && v >= -2.0 && v < board.rows + 1.0)) {
    return -1.0;  // off the board
  }
  const int i = static_cast<int>(std::floor(u));
  const int j = static_cast<int>(std::floor(v));
  if (i == -2 || i == board.cols || j == -2 || j == board.rows) return kWhite;  // margin
  return (i + j + 4) % 2 == 0 ? kBlack : kWhite;  // square (-1, -1) is black
}

// Which cell of the board a board-frame point lies in: -1 off the board.
int BoardCell(const CheckerboardSpec& board, double x, double y) {
  const double u = x / board.square_m;
  const double v = y / board.square_m;
  if (!(u >= -2.0 && u < board.cols + 1.0 && v >= -2.0 && v < board.rows + 1.0)) return -1;
  return static_cast<int>(std::floor(v) + 2) * (board.cols + 3) +
         static_cast<int>(std::floor(u) + 2);
}

// A ray from the camera centre, in the board frame.
struct BoardRay {
  Eigen::Vector3d origin;     // the camera centre
  Eigen::Vector3d direction;  // not normalised

  // Where the ray meets the board plane z = 0; false when it does not (parallel or behind).
  bool Hit(Eigen::Vector2d* point) const {
    const double lambda = -origin.z() / direction.z();
    if (!(lambda > 0.0) || !std::isfinite(lambda)) return false;
    *point = origin.head<2>() + lambda * direction.head<2>();
    return true;
  }

  // Radiance along the ray: albedo x (0.5 + 0.5 cos(incidence)) for a light at the camera, or
  // the background.
  double Radiance(const CheckerboardSpec& board) const {
    Eigen::Vector2d point;
    if (!Hit(&point)) return kBackground;
    const double albedo = BoardAlbedo(board, point.x(), point.y());
    if (albedo < 0.0) return kBackground;
    const double cos_incidence = std::abs(direction.z()) / direction.norm();
    return albedo * (0.5 + 0.5 * cos_incidence);
  }
};

// The Hammersley point set in the unit square: x = (i + 0.5) / n, y = the base-2 radical
// inverse of i (bit-reversed i, for n a power of two), offset to the stratum's centre.
std::vector<Eigen::Vector2d> HammersleyPoints(int n) {
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i < n; ++i) {
    double inverse = 0.0;
    double digit = 0.5;
    for (int bits = i; bits > 0; bits >>= 1, digit *= 0.5) {
      if (bits & 1) inverse += digit;
    }
    points.emplace_back((i + 0.5) / n, inverse + 0.5 / n);
  }
  return points;
}

// Samples of the board outline with its margin, for the visibility checks.
std::vector<Eigen::Vector3d> BoardOutline(const CheckerboardSpec& board) {
  const double s = board.square_m;
  const Eigen::Vector2d low(-2.0 * s, -2.0 * s);
  const Eigen::Vector2d high((board.cols + 1.0) * s, (board.rows + 1.0) * s);
  const std::array<Eigen::Vector2d, 4> corners = {low, Eigen::Vector2d(high.x(), low.y()), high,
                                                  Eigen::Vector2d(low.x(), high.y())};
  constexpr int kSamplesPerSide = 12;
  std::vector<Eigen::Vector3d> outline;
  for (int side = 0; side < 4; ++side) {
    for (int k = 0; k < kSamplesPerSide; ++k) {
      const Eigen::Vector2d point =
          corners[side] + (corners[(side + 1) % 4] - corners[side]) * k / kSamplesPerSide;
      outline.emplace_back(point.x(), point.y(), 0.0);
    }
  }
  return outline;
}

enum class BoardFit { kUsable, kOutside, kCornersTooClose };

// Whether the whole board is usable in the view: every outline and corner point projects into
// the image inside the field of view (the lens's, max_view_angle, and the model's) and the
// board faces the camera at no more than kMaxIncidenceDeg (else kOutside), and neighbouring
// corners are at least kMinCornerSpacingPx apart (else kCornersTooClose).
BoardFit CheckBoardView(const Camera& camera, double max_view_angle, const CheckerboardSpec& board,
                        const std::vector<Eigen::Vector3d>& outline,
                        const Eigen::Isometry3d& cam_from_board) {
  const Eigen::Vector3d normal = cam_from_board.rotation().col(2);
  const double min_cos_incidence = std::cos(kMaxIncidenceDeg * kDegToRad);
  const double min_cos_view = std::cos(max_view_angle);
  auto inside = [&](const Eigen::Vector3d& point_cam, Eigen::Vector2d* pixel) {
    return point_cam.z() >= min_cos_view * point_cam.norm() &&
           camera.Project(point_cam, pixel) == ProjectionStatus::kValid &&
           pixel->x() >= kImageMarginPx && pixel->y() >= kImageMarginPx &&
           pixel->x() <= camera.Width() - 1 - kImageMarginPx &&
           pixel->y() <= camera.Height() - 1 - kImageMarginPx;
  };
  Eigen::Vector2d pixel;
  for (const Eigen::Vector3d& point : outline) {
    const Eigen::Vector3d point_cam = cam_from_board * point;
    // The camera sits on the board's -z side (its front) and sees it at a usable angle.
    if (point_cam.normalized().dot(normal) < min_cos_incidence) return BoardFit::kOutside;
    if (!inside(point_cam, &pixel)) return BoardFit::kOutside;
  }
  std::vector<Eigen::Vector2d> corners;
  for (const Eigen::Vector3d& point : CheckerboardCorners(board)) {
    if (!inside(cam_from_board * point, &pixel)) return BoardFit::kOutside;
    corners.push_back(pixel);
  }
  for (int r = 0; r < board.rows; ++r) {
    for (int c = 0; c < board.cols; ++c) {
      const Eigen::Vector2d& p = corners[r * board.cols + c];
      const bool close_right =
          c + 1 < board.cols && (corners[r * board.cols + c + 1] - p).norm() < kMinCornerSpacingPx;
      const bool close_below = r + 1 < board.rows &&
                               (corners[(r + 1) * board.cols + c] - p).norm() < kMinCornerSpacingPx;
      if (close_right || close_below) return BoardFit::kCornersTooClose;
    }
  }
  return BoardFit::kUsable;
}

SimulationConfig Validated(const SimulationConfig& config) {
  ValidateConfig(config);
  return config;
}

std::string FrameName(int index) {
  char name[32];
  std::snprintf(name, sizeof(name), "%06d.png", index);
  return name;
}

}  // namespace

// As the pipe renderer has it (simulation.cc).
double MaxViewAngle(const SimulationConfig& config) {
  const bool circular = config.camera_model == "fisheye-poly" && config.fov_deg >= 180.0;
  return circular ? 0.5 * config.fov_deg * kDegToRad : M_PI;
}

CheckerboardSpec CheckerboardFromConfig(const SimulationConfig& config) {
  CheckerboardSpec board;
  board.cols = config.board_cols;
  board.rows = config.board_rows;
  board.square_m = config.board_square_m;
  return board;
}

std::vector<Eigen::Isometry3d> GenerateCheckerboardPoses(const SimulationConfig& config,
                                                         const Camera& camera) {
  const CheckerboardSpec board = CheckerboardFromConfig(config);
  const std::vector<Eigen::Vector3d> outline = BoardOutline(board);
  const double s = board.square_m;
  const Eigen::Vector3d centre_board(0.5 * (board.cols - 1) * s, 0.5 * (board.rows - 1) * s, 0.0);
  const double diagonal_m = std::hypot((board.cols + 3) * s, (board.rows + 3) * s);
  const double field = std::min(config.fov_deg, kMaxFieldDeg) * kDegToRad;
  const double max_view_angle = MaxViewAngle(config);
  const Eigen::Vector2d image_centre(0.5 * (camera.Width() - 1), 0.5 * (camera.Height() - 1));
  const Eigen::Vector2d half_extent(0.5 * camera.Width() - kImageMarginPx,
                                    0.5 * camera.Height() - kImageMarginPx);
  const std::array<Eigen::Vector2d, 8> ring = {Eigen::Vector2d(-1, -1), Eigen::Vector2d(1, 1),
                                               Eigen::Vector2d(1, -1),  Eigen::Vector2d(-1, 1),
                                               Eigen::Vector2d(-1, 0),  Eigen::Vector2d(1, 0),
                                               Eigen::Vector2d(0, -1),  Eigen::Vector2d(0, 1)};

  std::mt19937_64 rng(MixSeed(config.seed, kBoardPoseStream));
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<Eigen::Isometry3d> poses;
  for (int i = 0; i < config.frames; ++i) {
    Eigen::Vector2d anchor = Eigen::Vector2d::Zero();
    if (i >= 1 && i <= 8) {
      anchor = ring[i - 1];
    } else if (i > 8) {
      anchor = Eigen::Vector2d(2.0 * uniform(rng) - 1.0, 2.0 * uniform(rng) - 1.0);
    }
    const bool rim = i >= 1 && i <= 8;
    // A board that leaves the image or the field of view is aimed further in; one whose
    // corners crowd together is made larger.
    double anchor_scale = 1.0;
    double size_scale = 1.0;
    bool placed = false;
    for (int attempt = 0; attempt < kMaxPlacementAttempts && !placed; ++attempt) {
      const double size_fraction =
          size_scale *
          (rim ? kMinRimSizeFraction + (kMaxRimSizeFraction - kMinRimSizeFraction) * uniform(rng)
               : kMinSizeFraction + (kMaxSizeFraction - kMinSizeFraction) * uniform(rng));
      const double tilt = kMaxTiltDeg * kDegToRad * std::sqrt(uniform(rng));
      const double tilt_azimuth = 2.0 * M_PI * uniform(rng);
      const double spin = kMaxSpinDeg * kDegToRad * (2.0 * uniform(rng) - 1.0);
      Eigen::Vector3d direction;
      if (!camera.Unproject(image_centre + anchor_scale * anchor.cwiseProduct(half_extent),
                            &direction) ||
          direction.z() < std::cos(max_view_angle)) {
        anchor_scale *= 0.97;
        continue;
      }
      // The board's +z starts along the viewing direction (the camera sees its front), its x
      // and y along the image's x and y, then it is spun and tilted.
      const Eigen::Vector3d reference =
          std::abs(direction.y()) < 0.9 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitX();
      Eigen::Matrix3d base;
      base.col(0) = reference.cross(direction).normalized();
      base.col(1) = direction.cross(base.col(0));
      base.col(2) = direction;
      const Eigen::Vector3d tilt_axis =
          std::cos(tilt_azimuth) * base.col(0) + std::sin(tilt_azimuth) * base.col(1);
      const Eigen::Matrix3d rotation = Eigen::AngleAxisd(tilt, tilt_axis).toRotationMatrix() *
                                       Eigen::AngleAxisd(spin, direction).toRotationMatrix() * base;
      const double distance =
          0.5 * diagonal_m / std::tan(0.5 * std::min(size_fraction * field, 0.9 * M_PI));
      Eigen::Isometry3d cam_from_board = Eigen::Isometry3d::Identity();
      cam_from_board.linear() = rotation;
      cam_from_board.translation() = distance * direction - rotation * centre_board;
      switch (CheckBoardView(camera, max_view_angle, board, outline, cam_from_board)) {
        case BoardFit::kUsable:
          poses.push_back(cam_from_board);
          placed = true;
          break;
        case BoardFit::kOutside:
          anchor_scale *= 0.97;
          break;
        case BoardFit::kCornersTooClose:
          size_scale *= 1.05;
          break;
      }
    }
    if (!placed) {
      throw InputError("layout checkerboard: cannot place view " + std::to_string(i) +
                       " of the board inside the image; check board_cols, board_rows and the "
                       "camera keys");
    }
  }
  return poses;
}

CheckerboardRenderer::CheckerboardRenderer(const Camera& camera, const CheckerboardSpec& board,
                                           double max_view_angle)
    : camera_(camera), board_(board) {
  const double min_cos_view = std::cos(max_view_angle);
  const int width = camera.Width();
  const int height = camera.Height();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  corner_bearings_.resize(static_cast<std::size_t>(width + 1) * (height + 1));
  for (int y = 0; y <= height; ++y) {
    for (int x = 0; x <= width; ++x) {
      Eigen::Vector3d bearing;
      if (!camera.Unproject(Eigen::Vector2d(x - 0.5, y - 0.5), &bearing) ||
          bearing.z() < min_cos_view) {
        bearing = Eigen::Vector3d(nan, nan, nan);
      }
      corner_bearings_[static_cast<std::size_t>(y) * (width + 1) + x] = bearing;
    }
  }
}

cv::Mat CheckerboardRenderer::RenderRadiance(const Eigen::Isometry3d& cam_from_board) const {
  const int width = camera_.Width();
  const int height = camera_.Height();
  const Eigen::Matrix3d board_from_cam_rotation = cam_from_board.rotation().transpose();
  const Eigen::Vector3d camera_centre = -board_from_cam_rotation * cam_from_board.translation();
  std::vector<Eigen::Vector3d> rays(corner_bearings_.size());
  for (std::size_t k = 0; k < rays.size(); ++k)
    rays[k] = board_from_cam_rotation * corner_bearings_[k];

  const std::vector<Eigen::Vector2d> centre_sample = {Eigen::Vector2d(0.5, 0.5)};
  const std::vector<Eigen::Vector2d> hammersley = HammersleyPoints(kSupersamples);
  cv::Mat radiance(height, width, CV_32F);
  const std::size_t stride = width + 1;
  for (int y = 0; y < height; ++y) {
    float* row = radiance.ptr<float>(y);
    for (int x = 0; x < width; ++x) {
      const std::size_t k = static_cast<std::size_t>(y) * stride + x;
      const std::array<const Eigen::Vector3d*, 4> corner = {
          &rays[k], &rays[k + 1], &rays[k + stride], &rays[k + stride + 1]};
      if (std::any_of(corner.begin(), corner.end(),
                      [](const Eigen::Vector3d* ray) { return std::isnan(ray->x()); })) {
        row[x] = 0.0f;  // outside the field of view: no light reaches the sensor
        continue;
      }
      // A pixel whose four corners see the same cell is inside it (cells are convex and a
      // pixel's footprint is nearly a parallelogram): one sample does. Otherwise supersample.
      std::array<int, 4> cells;
      for (int c = 0; c < 4; ++c) {
        Eigen::Vector2d point;
        cells[c] = BoardRay{camera_centre, *corner[c]}.Hit(&point)
                       ? BoardCell(board_, point.x(), point.y())
                       : -2;
      }
      const bool uniform =
          std::all_of(cells.begin(), cells.end(), [&](int cell) { return cell == cells[0]; });
      const std::vector<Eigen::Vector2d>& samples = uniform ? centre_sample : hammersley;
      double sum = 0.0;
      for (const Eigen::Vector2d& f : samples) {
        // Bilinear interpolation of the corner rays: the lens map is smooth on a pixel's scale,
        // so the error is second order in the pixel size.
        const Eigen::Vector3d direction =
            (1 - f.y()) * ((1 - f.x()) * *corner[0] + f.x() * *corner[1]) +
            f.y() * ((1 - f.x()) * *corner[2] + f.x() * *corner[3]);
        sum += BoardRay{camera_centre, direction}.Radiance(board_);
      }
      row[x] = static_cast<float>(sum / samples.size());
    }
  }
  cv::GaussianBlur(radiance, radiance, cv::Size(0, 0), kDefocusSigmaPx);
  return radiance;
}

std::vector<Eigen::Vector2d> ProjectCheckerboardCorners(const Camera& camera,
                                                        const CheckerboardSpec& board,
                                                        const Eigen::Isometry3d& cam_from_board) {
  std::vector<Eigen::Vector2d> pixels;
  for (const Eigen::Vector3d& point : CheckerboardCorners(board)) {
    Eigen::Vector2d pixel;
    camera.Project(cam_from_board * point, &pixel);
    pixels.push_back(pixel);
  }
  return pixels;
}

CheckerboardSimulation::CheckerboardSimulation(const SimulationConfig& config)
    : config_(Validated(config)),
      camera_(MakeSimulatedCamera(config_)),
      board_(CheckerboardFromConfig(config_)),
      cam_from_board_(GenerateCheckerboardPoses(config_, camera_)),
      renderer_(camera_, board_, MaxViewAngle(config_)),
      vignetting_(VignettingMap(camera_, config_.vignetting)) {}

cv::Mat CheckerboardSimulation::RenderImage(int index) const {
  SensorOptions sensor;
  sensor.exposure = config_.exposure_target;  // a white square lit head-on
  sensor.noise_sigma = config_.noise_sigma;
  sensor.electrons_per_grey_level = config_.electrons_per_grey_level;
  return ApplySensor(renderer_.RenderRadiance(cam_from_board_.at(index)), vignetting_, sensor,
                     MixSeed(config_.seed, kBoardNoiseStream, index));
}

std::vector<Eigen::Vector2d> CheckerboardSimulation::TrueCorners(int index) const {
  return ProjectCheckerboardCorners(camera_, board_, cam_from_board_.at(index));
}

SimulationSummary SimulateCheckerboardDataset(const SimulationConfig& config,
                                              const std::filesystem::path& out) {
  const CheckerboardSimulation simulation(config);
  StagingDirectory staging_folder(out, "--out", "simulation.yaml");
  const std::filesystem::path& staging = staging_folder.path();
  Timer timer;

  std::filesystem::create_directories(staging / "images");
  Trajectory board_from_cam;
  ProgressBar progress("simulate", config.frames);
  for (int i = 0; i < config.frames; ++i) {
    const std::filesystem::path path = staging / "images" / FrameName(i);
    if (!cv::imwrite(path.string(), simulation.RenderImage(i), {cv::IMWRITE_PNG_COMPRESSION, 1})) {
      throw InputError("cannot write " + path.string());
    }
    const Eigen::Isometry3d world_from_cam = simulation.cam_from_board()[i].inverse();
    StampedPose pose;
    pose.timestamp = i / config.fps;
    pose.rotation = Eigen::Quaterniond(world_from_cam.rotation());
    pose.position = world_from_cam.translation();
    board_from_cam.push_back(pose);
    progress.Update(i + 1);
  }
  progress.Finish();

  const CheckerboardSpec& board = simulation.board();
  WriteCameraYaml(staging / "camera.yaml", simulation.camera());
  WriteTumTrajectory(staging / "groundtruth.tum", board_from_cam);
  WriteTextFileAtomically(
      staging / "board.yaml",
      "# Calibration board of this dataset: inner corners and square size (pipescope calibrate\n"
      "# --board COLSxROWS --square-m S). groundtruth.tum holds board_from_cam of each view.\n"
      "cols: " +
          std::to_string(board.cols) + "\nrows: " + std::to_string(board.rows) +
          "\nsquare_m: " + GetConfigValue(config, "board_square_m") + "\n");
  WriteTextFileAtomically(staging / "simulation.yaml", SimulationConfigYaml(config));
  staging_folder.Commit();

  SimulationSummary summary;
  summary.frames = config.frames;
  summary.seconds = timer.ElapsedSeconds();
  return summary;
}

}  // namespace pipescope
