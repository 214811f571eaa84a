#pragma once

#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "pipescope/camera/camera.h"

namespace pipescope {

// The dense grey appearance map of 001 §IV-B: points on the fitted cylinder of a straight
// section, each given the mean grey value over all key frames that see it near the fisheye's
// periphery (colatitude 50° < theta < 90°, where the ground resolution is highest).

// A straight section's fitted cylinder (001 §III-C) in the world frame. Its wall is mapped
// between begin_m and end_m, metres along the axis from axis_point.
struct DenseMapCylinder {
  Eigen::Vector3d axis_point = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis_direction = Eigen::Vector3d::UnitZ();  // normalised by the grid
  double radius_m = 0.0;
  double begin_m = 0.0;
  double end_m = 0.0;
  // Where phi = 0 points from the axis; its along-axis part is removed. Unset: the world axis
  // (X, then Y, then Z) least aligned with the cylinder's axis, made perpendicular to it.
  std::optional<Eigen::Vector3d> reference_direction;
};

// The sample points on the wall. Row i (along the axis) is centred at s_i = begin_m + (i + 0.5)
// axial_step_m(), with axial_step_m() the extent divided by round(extent / spacing); column j
// lies at phi_j = j angular_step_rad(), with round(2 pi r / spacing) columns. phi turns
// right-handedly about the axis direction, from reference_direction() towards
// axis_direction() x reference_direction().
class DenseMapGrid {
 public:
  // Throws InputError for a non-positive or non-finite spacing or radius, an empty extent
  // (end_m <= begin_m), a zero axis direction, a reference direction along the axis, or a grid
  // too large for one image.
  DenseMapGrid(const DenseMapCylinder& cylinder, double spacing_m);

  int rows() const { return rows_; }
  int cols() const { return cols_; }
  double radius_m() const { return radius_m_; }
  double axial_step_m() const { return axial_step_m_; }
  double angular_step_rad() const { return angular_step_rad_; }
  const Eigen::Vector3d& axis_point() const { return axis_point_; }
  const Eigen::Vector3d& axis_direction() const { return axis_direction_; }
  const Eigen::Vector3d& reference_direction() const { return reference_direction_; }
  // axis_direction() x reference_direction(): phi = 90°.
  const Eigen::Vector3d& quarter_turn_direction() const { return quarter_turn_direction_; }

  // Metres along the axis from axis_point() of row `row`'s centre.
  double AxialPositionM(int row) const { return begin_m_ + (row + 0.5) * axial_step_m_; }
  double AngleRad(int col) const { return col * angular_step_rad_; }
  // The world point of cell (row, col) on the wall.
  Eigen::Vector3d CellPoint(int row, int col) const;

 private:
  Eigen::Vector3d axis_point_;
  Eigen::Vector3d axis_direction_;
  Eigen::Vector3d reference_direction_;
  Eigen::Vector3d quarter_turn_direction_;
  double radius_m_;
  double begin_m_;
  int rows_;
  int cols_;
  double axial_step_m_;
  double angular_step_rad_;
};

struct DenseAppearanceOptions {
  // Distance between sample points on the wall, along the axis and around it, metres.
  double spacing_m = 0.002;
  // Only observations with min < theta < max count; theta is the angle between the camera's
  // optical axis (+Z) and the ray to the point (001 §IV-B).
  double min_colatitude_deg = 50.0;
  double max_colatitude_deg = 90.0;
  // Weight each view by sin(pi (theta - min) / (max - min)) instead of 001's plain mean.
  bool colatitude_taper = false;
};

// A seen cell as a 3D point of the map.
struct DenseMapPoint {
  Eigen::Vector3d position;  // world frame, metres
  float grey = 0.0f;         // mean over the key frames that saw it
  int row = 0;
  int col = 0;
};

struct DenseAppearanceMap {
  cv::Mat mean_grey;  // CV_32F, rows x cols of the grid; NaN where no key frame saw the cell
  cv::Mat count;      // CV_32S, how many key frames each cell's mean is over
  std::vector<DenseMapPoint> points;  // the seen cells, row by row
};

// Builds the map one key frame at a time, so a long route never holds more than one image: the
// sum and count of each cell are kept, and the mean formed when asked.
class DenseAppearanceAccumulator {
 public:
  // Throws InputError for a bad grid (DenseMapGrid) or colatitude limits outside
  // 0 <= min < max <= 180.
  explicit DenseAppearanceAccumulator(const DenseMapCylinder& cylinder,
                                      const DenseAppearanceOptions& options = {});

  // Adds the grey value (bilinear, pixel centres at integer coordinates) of every cell that
  // `camera` at `cam_from_world` sees within the colatitude band and on the image. `grey` is
  // CV_8UC1 or CV_32FC1 of the camera's size, else InputError; non-finite pixels are skipped.
  // Returns how many cells received a value.
  int AddKeyFrame(const Camera& camera, const Eigen::Isometry3d& cam_from_world,
                  const cv::Mat& grey);

  const DenseMapGrid& grid() const { return grid_; }
  int num_key_frames() const { return num_key_frames_; }

  DenseAppearanceMap Result() const;

 private:
  DenseMapGrid grid_;
  double min_colatitude_rad_;
  double max_colatitude_rad_;
  bool taper_ = false;
  cv::Mat sum_;     // CV_64F
  cv::Mat weight_;  // CV_64F: the sum of the views' weights
  cv::Mat count_;   // CV_32S
  int num_key_frames_ = 0;
};

}  // namespace pipescope
