#pragma once

// Calibration views of a planar checkerboard (layout `checkerboard`, preset `checkerboard`;
// issue 4, 001 §II): a board at varied poses seen through any camera model, with anti-aliased
// squares and the sensor model of sensor.h, so `pipescope calibrate` can be measured against
// the true camera.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <opencv2/core.hpp>
#include <vector>

#include "pipescope/camera/calibration.h"
#include "pipescope/camera/camera.h"
#include "pipescope/synthetic/dataset_writer.h"
#include "pipescope/synthetic/simulation_config.h"

namespace pipescope {

// board_cols, board_rows, board_square_m of the config.
CheckerboardSpec CheckerboardFromConfig(const SimulationConfig& config);

// config.frames board poses (cam_from_board; board frame as CheckerboardCorners), deterministic
// for config.seed. View 0 is centred, views 1-8 aim at the image corners and edge midpoints with
// small boards (18-30 % of the field of view, capped at 110 degrees, across the board's
// diagonal), the rest at random places with larger ones (45-80 %); each board is tilted up to 50
// degrees about a random axis and turned up to 30 degrees in its plane. A board that leaves the
// image or the field of view (MaxViewAngle) or is seen at more than 75 degrees incidence is aimed
// further in; one whose corners come closer than 6 px is made larger. So the views reach the
// image corners, and on a wide fisheye-poly the rim past 90 degrees.
std::vector<Eigen::Isometry3d> GenerateCheckerboardPoses(const SimulationConfig& config,
                                                         const Camera& camera);

// The lens's field of view, radians: half of fov_deg for a fisheye-poly of 180 degrees or more
// (a circular image, as the pipe renderer has it), else pi (the model's own limit applies).
double MaxViewAngle(const SimulationConfig& config);

// Renders board views through one camera. The board is (cols + 1) x (rows + 1) squares with
// black corner squares and a white margin one square wide, in front of a grey background.
class CheckerboardRenderer {
 public:
  // Rays more than `max_view_angle` from the optical axis do not pass the lens.
  CheckerboardRenderer(const Camera& camera, const CheckerboardSpec& board,
                       double max_view_angle = M_PI);

  // Linear radiance (CV_32F, 1 = a white square lit head-on): albedo (white 1, black 0.05,
  // background 0.25) times the shading 0.5 + 0.5 cos(incidence) of a light at the camera.
  // Every pixel is the mean over its footprint: pixels whose footprint crosses an edge of the
  // pattern are supersampled with 256 points, with rays interpolated between the pixel's corner
  // bearings. Pixels outside the lens's field of view are black.
  cv::Mat RenderRadiance(const Eigen::Isometry3d& cam_from_board) const;

 private:
  const Camera& camera_;
  CheckerboardSpec board_;
  // Unit bearings of the pixel corners, (width + 1) x (height + 1), NaN outside the field of
  // view; corner (x, y) sits at pixel coordinates (x - 0.5, y - 0.5).
  std::vector<Eigen::Vector3d> corner_bearings_;
};

// The true pixels of the inner corners (CheckerboardCorners order).
std::vector<Eigen::Vector2d> ProjectCheckerboardCorners(const Camera& camera,
                                                        const CheckerboardSpec& board,
                                                        const Eigen::Isometry3d& cam_from_board);

// Everything a checkerboard config describes, assembled: camera, board, view poses, renderer
// and sensor. The dataset writer and the tests render through it.
class CheckerboardSimulation {
 public:
  explicit CheckerboardSimulation(const SimulationConfig& config);  // validates the config

  // The 8-bit image of view `index`: radiance, vignetting, exposure (a white square lit
  // head-on at exposure_target), shot and read noise; deterministic for config.seed.
  cv::Mat RenderImage(int index) const;
  // The true pixels of view `index`'s inner corners (CheckerboardCorners order).
  std::vector<Eigen::Vector2d> TrueCorners(int index) const;

  const Camera& camera() const { return camera_; }
  const CheckerboardSpec& board() const { return board_; }
  const std::vector<Eigen::Isometry3d>& cam_from_board() const { return cam_from_board_; }

 private:
  SimulationConfig config_;
  Camera camera_;
  CheckerboardSpec board_;
  std::vector<Eigen::Isometry3d> cam_from_board_;
  CheckerboardRenderer renderer_;
  cv::Mat vignetting_;
};

// Writes a calibration dataset into `out` atomically (a staging folder renamed at the end):
// images/NNNNNN.png, camera.yaml (the truth), board.yaml (`cols`, `rows` of inner corners,
// `square_m`), groundtruth.tum (board_from_cam of each view: the board frame is the world, so
// the file keeps the camera-to-world convention of GUIDE §3) and simulation.yaml.
SimulationSummary SimulateCheckerboardDataset(const SimulationConfig& config,
                                              const std::filesystem::path& out);

}  // namespace pipescope
