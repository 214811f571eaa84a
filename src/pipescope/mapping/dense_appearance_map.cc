#include "pipescope/mapping/dense_appearance_map.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <limits>
#include <string>

#include "pipescope/util/error.h"

namespace pipescope {
namespace {

// The world axis least aligned with `axis`, made perpendicular to it: a fixed phi = 0 for a
// caller with no preference.
Eigen::Vector3d DefaultReferenceDirection(const Eigen::Vector3d& axis) {
  int least_aligned = 0;
  for (int k = 1; k < 3; ++k) {
    if (std::abs(axis[k]) < std::abs(axis[least_aligned])) least_aligned = k;
  }
  const Eigen::Vector3d world_axis = Eigen::Vector3d::Unit(least_aligned);
  return (world_axis - world_axis.dot(axis) * axis).normalized();
}

// Pixel centres at integer coordinates; the image covers [-0.5, size - 0.5], so the half pixel
// at the border repeats the edge pixel.
template <typename Pixel>
float SampleBilinear(const cv::Mat& image, double x, double y) {
  x = std::clamp(x, 0.0, static_cast<double>(image.cols - 1));
  y = std::clamp(y, 0.0, static_cast<double>(image.rows - 1));
  const int x0 = static_cast<int>(x);
  const int y0 = static_cast<int>(y);
  const int x1 = std::min(x0 + 1, image.cols - 1);
  const int y1 = std::min(y0 + 1, image.rows - 1);
  const double fx = x - x0;
  const double fy = y - y0;
  const Pixel* row0 = image.ptr<Pixel>(y0);
  const Pixel* row1 = image.ptr<Pixel>(y1);
  const double top = (1.0 - fx) * row0[x0] + fx * row0[x1];
  const double bottom = (1.0 - fx) * row1[x0] + fx * row1[x1];
  return static_cast<float>((1.0 - fy) * top + fy * bottom);
}

// Colatitude of a camera-frame point: the angle from the optical axis +Z.
double Colatitude(const Eigen::Vector3d& point_cam) {
  return std::atan2(point_cam.head<2>().norm(), point_cam.z());
}

}  // namespace

DenseMapGrid::DenseMapGrid(const DenseMapCylinder& cylinder, double spacing_m) {
  if (!(spacing_m > 0.0) || !std::isfinite(spacing_m)) {
    throw InputError("dense map: the grid spacing must be positive, not " +
                     std::to_string(spacing_m));
  }
  if (!(cylinder.radius_m > 0.0) || !std::isfinite(cylinder.radius_m)) {
    throw InputError("dense map: the cylinder radius must be positive, not " +
                     std::to_string(cylinder.radius_m));
  }
  if (!std::isfinite(cylinder.begin_m) || !std::isfinite(cylinder.end_m) ||
      !(cylinder.end_m > cylinder.begin_m)) {
    throw InputError("dense map: the extent along the axis [" + std::to_string(cylinder.begin_m) +
                     ", " + std::to_string(cylinder.end_m) + "] is empty");
  }
  if (!cylinder.axis_point.allFinite() || !cylinder.axis_direction.allFinite() ||
      cylinder.axis_direction.norm() < 1e-12) {
    throw InputError("dense map: the cylinder axis needs a finite point and a non-zero direction");
  }
  axis_point_ = cylinder.axis_point;
  axis_direction_ = cylinder.axis_direction.normalized();
  if (cylinder.reference_direction) {
    const Eigen::Vector3d& given = *cylinder.reference_direction;
    const Eigen::Vector3d across = given - given.dot(axis_direction_) * axis_direction_;
    if (!given.allFinite() || across.norm() < 1e-9 * given.norm() || across.norm() < 1e-12) {
      throw InputError("dense map: the phi = 0 reference direction must not lie along the axis");
    }
    reference_direction_ = across.normalized();
  } else {
    reference_direction_ = DefaultReferenceDirection(axis_direction_);
  }
  quarter_turn_direction_ = axis_direction_.cross(reference_direction_);
  radius_m_ = cylinder.radius_m;
  begin_m_ = cylinder.begin_m;

  const double extent_m = cylinder.end_m - cylinder.begin_m;
  const double rows = std::max(1.0, std::round(extent_m / spacing_m));
  const double cols = std::max(3.0, std::round(2.0 * M_PI * radius_m_ / spacing_m));
  if (rows * cols > static_cast<double>(INT_MAX)) {
    throw InputError("dense map: " + std::to_string(rows) + " x " + std::to_string(cols) +
                     " cells is too many for one section; use a larger spacing");
  }
  rows_ = static_cast<int>(rows);
  cols_ = static_cast<int>(cols);
  axial_step_m_ = extent_m / rows_;
  angular_step_rad_ = 2.0 * M_PI / cols_;
}

Eigen::Vector3d DenseMapGrid::CellPoint(int row, int col) const {
  const double phi = AngleRad(col);
  return axis_point_ + AxialPositionM(row) * axis_direction_ +
         radius_m_ *
             (std::cos(phi) * reference_direction_ + std::sin(phi) * quarter_turn_direction_);
}

DenseAppearanceAccumulator::DenseAppearanceAccumulator(const DenseMapCylinder& cylinder,
                                                       const DenseAppearanceOptions& options)
    : grid_(cylinder, options.spacing_m),
      min_colatitude_rad_(options.min_colatitude_deg * M_PI / 180.0),
      max_colatitude_rad_(options.max_colatitude_deg * M_PI / 180.0),
      taper_(options.colatitude_taper) {
  if (!(options.min_colatitude_deg >= 0.0) || !(options.max_colatitude_deg <= 180.0) ||
      !(options.min_colatitude_deg < options.max_colatitude_deg)) {
    throw InputError(
        "dense map: the colatitude band must satisfy 0 <= min < max <= 180 degrees, "
        "not (" +
        std::to_string(options.min_colatitude_deg) + ", " +
        std::to_string(options.max_colatitude_deg) + ")");
  }
  sum_ = cv::Mat::zeros(grid_.rows(), grid_.cols(), CV_64F);
  weight_ = cv::Mat::zeros(grid_.rows(), grid_.cols(), CV_64F);
  count_ = cv::Mat::zeros(grid_.rows(), grid_.cols(), CV_32S);
}

int DenseAppearanceAccumulator::AddKeyFrame(const Camera& camera,
                                            const Eigen::Isometry3d& cam_from_world,
                                            const cv::Mat& grey) {
  if (grey.type() != CV_8UC1 && grey.type() != CV_32FC1) {
    throw InputError("dense map: a key frame image must be CV_8UC1 or CV_32FC1");
  }
  if (grey.cols != camera.Width() || grey.rows != camera.Height()) {
    throw InputError("dense map: a key frame image is " + std::to_string(grey.cols) + "x" +
                     std::to_string(grey.rows) + " but the camera's is " +
                     std::to_string(camera.Width()) + "x" + std::to_string(camera.Height()));
  }
  ++num_key_frames_;

  // The wall in the camera frame: row centre + ring offset, each computed once per frame.
  const Eigen::Matrix3d& rotation = cam_from_world.linear();
  const Eigen::Vector3d axis_point_cam = cam_from_world * grid_.axis_point();
  const Eigen::Vector3d axis_cam = rotation * grid_.axis_direction();
  std::vector<Eigen::Vector3d> ring_cam(grid_.cols());
  for (int col = 0; col < grid_.cols(); ++col) {
    const double phi = grid_.AngleRad(col);
    ring_cam[col] = grid_.radius_m() * rotation *
                    (std::cos(phi) * grid_.reference_direction() +
                     std::sin(phi) * grid_.quarter_turn_direction());
  }

  int cells_added = 0;
  Eigen::Vector2d pixel;
  for (int row = 0; row < grid_.rows(); ++row) {
    const Eigen::Vector3d row_centre_cam = axis_point_cam + grid_.AxialPositionM(row) * axis_cam;
    // The ring lies within the radius of its centre, so its rays are within asin(r / |centre|)
    // of the centre's: a ring wholly outside the band is skipped without projecting it, which
    // keeps a long section cheap for a key frame that sees a short stretch of it.
    const double centre_distance = row_centre_cam.norm();
    if (centre_distance > grid_.radius_m()) {
      const double spread = std::asin(grid_.radius_m() / centre_distance);
      const double centre_colatitude = Colatitude(row_centre_cam);
      if (centre_colatitude + spread <= min_colatitude_rad_ ||
          centre_colatitude - spread >= max_colatitude_rad_) {
        continue;
      }
    }
    double* sum = sum_.ptr<double>(row);
    double* weight_sum = weight_.ptr<double>(row);
    int* count = count_.ptr<int>(row);
    for (int col = 0; col < grid_.cols(); ++col) {
      const Eigen::Vector3d point_cam = row_centre_cam + ring_cam[col];
      // 001 §IV-B: only the periphery of the fisheye image, 50° < theta < 90° by default.
      const double colatitude = Colatitude(point_cam);
      if (!(colatitude > min_colatitude_rad_ && colatitude < max_colatitude_rad_)) continue;
      // kValid: within the lens's field of view and on the image.
      if (camera.Project(point_cam, &pixel) != ProjectionStatus::kValid) continue;
      const float value = grey.type() == CV_8UC1
                              ? SampleBilinear<uchar>(grey, pixel.x(), pixel.y())
                              : SampleBilinear<float>(grey, pixel.x(), pixel.y());
      if (!std::isfinite(value)) continue;
      // With the taper, a view counts less the nearer it is to the band's edges, so a cell's
      // mean does not step where one view enters or leaves it (their lighting differs).
      const double weight = taper_ ? std::sin(M_PI * (colatitude - min_colatitude_rad_) /
                                              (max_colatitude_rad_ - min_colatitude_rad_))
                                   : 1.0;
      sum[col] += weight * value;
      weight_sum[col] += weight;
      ++count[col];
      ++cells_added;
    }
  }
  return cells_added;
}

DenseAppearanceMap DenseAppearanceAccumulator::Result() const {
  DenseAppearanceMap map;
  map.mean_grey = cv::Mat(grid_.rows(), grid_.cols(), CV_32F,
                          cv::Scalar(std::numeric_limits<float>::quiet_NaN()));
  map.count = count_.clone();
  for (int row = 0; row < grid_.rows(); ++row) {
    const double* sum = sum_.ptr<double>(row);
    const double* weight_sum = weight_.ptr<double>(row);
    const int* count = count_.ptr<int>(row);
    float* mean = map.mean_grey.ptr<float>(row);
    for (int col = 0; col < grid_.cols(); ++col) {
      if (count[col] == 0 || !(weight_sum[col] > 0.0)) continue;
      mean[col] = static_cast<float>(sum[col] / weight_sum[col]);
      map.points.push_back({grid_.CellPoint(row, col), mean[col], row, col});
    }
  }
  return map;
}

}  // namespace pipescope
