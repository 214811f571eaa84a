#include "pipescope/eval/dense_map_agreement.h"

#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <string>

#include "pipescope/util/error.h"

namespace pipescope {
namespace {

// `image` minus its Gaussian low-pass over the cells `valid` marks (normalised convolution:
// the blur of the valid values over the blur of the mask); 0 outside `valid`.
cv::Mat HighPassOverValid(const cv::Mat& image, const cv::Mat& valid, double sigma_cells) {
  cv::Mat values = cv::Mat::zeros(image.size(), CV_32F), weights;
  image.copyTo(values, valid);
  valid.convertTo(weights, CV_32F, 1.0 / 255.0);
  // Around the pipe the grid wraps: blur a copy padded with the other side's columns.
  const int pad = std::min(image.cols, static_cast<int>(std::ceil(4 * sigma_cells)) + 1);
  const auto wrap = [&](const cv::Mat& m) {
    cv::Mat padded;
    cv::copyMakeBorder(m, padded, 0, 0, pad, pad, cv::BORDER_WRAP);
    cv::GaussianBlur(padded, padded, cv::Size(0, 0), sigma_cells, sigma_cells,
                     cv::BORDER_REPLICATE);
    return cv::Mat(padded.colRange(pad, pad + m.cols).clone());
  };
  const cv::Mat low_values = wrap(values), low_weights = wrap(weights);
  cv::Mat result = cv::Mat::zeros(image.size(), CV_32F);
  for (int row = 0; row < image.rows; ++row) {
    for (int col = 0; col < image.cols; ++col) {
      if (!valid.at<uchar>(row, col)) continue;
      const float weight = low_weights.at<float>(row, col);
      result.at<float>(row, col) =
          values.at<float>(row, col) - low_values.at<float>(row, col) / std::max(weight, 1e-6f);
    }
  }
  return result;
}

}  // namespace

cv::Mat SimulatedAlbedoUnderGrid(const DenseMapGrid& grid,
                                 const std::vector<GridRowPlacement>& rows,
                                 const Simulation& simulation, double max_miss_m) {
  if (static_cast<int>(rows.size()) != grid.rows()) {
    throw InputError("dense map: " + std::to_string(rows.size()) + " row placements for " +
                     std::to_string(grid.rows()) + " grid rows");
  }
  const Scene& scene = simulation.layout().scene;
  const WallTexture& texture = simulation.texture();
  const double footprint = grid.axial_step_m();
  cv::Mat albedo(grid.rows(), grid.cols(), CV_32F);
  for (int row = 0; row < grid.rows(); ++row) {
    const GridRowPlacement& placement = rows[row];
    for (int col = 0; col < grid.cols(); ++col) {
      const Eigen::Vector3d point = placement.scene_from_map * grid.CellPoint(row, col);
      Ray ray;
      ray.origin = placement.viewpoint;
      ray.direction = (point - placement.viewpoint).normalized();
      WallHit hit;
      float value = std::numeric_limits<float>::quiet_NaN();
      if (ray.direction.allFinite() && scene.Intersect(ray, &hit) &&
          (hit.point - point).norm() <= max_miss_m) {
        const double circumference = 2.0 * M_PI * scene.sections()[hit.section].radius;
        value = texture.Albedo(hit.section, hit.h_m, hit.s_m, circumference, footprint);
      }
      albedo.at<float>(row, col) = value;
    }
  }
  return albedo;
}

DenseMapAgreement CorrelateWithAlbedo(const cv::Mat& grey, const cv::Mat& albedo,
                                      const DenseMapGrid& grid,
                                      const DenseMapAgreementOptions& options) {
  const cv::Size size(grid.cols(), grid.rows());
  if (grey.size() != size || albedo.size() != size) {
    throw InputError("dense map: the map is " + std::to_string(grey.cols) + "x" +
                     std::to_string(grey.rows) + " and the albedo " +
                     std::to_string(albedo.cols) + "x" + std::to_string(albedo.rows) +
                     " cells, the grid " + std::to_string(size.width) + "x" +
                     std::to_string(size.height));
  }
  if (grey.type() != CV_8UC1 && grey.type() != CV_32FC1) {
    throw InputError("dense map: the map must be 8-bit or float grey values");
  }
  if (!(options.high_pass_sigma_m > 0) || options.max_shift_cells < 0) {
    throw InputError("dense map agreement: high_pass_sigma_m must be positive and "
                     "max_shift_cells not negative");
  }
  cv::Mat map;
  grey.convertTo(map, CV_32F);
  const cv::Mat albedo_valid = albedo == albedo;
  // Map cells seen where the wall is: a cell over a T's opening shows what lies beyond it, and
  // its edge would leak into its neighbours' low-pass.
  const cv::Mat map_valid = (map > 0) & (map == map) & albedo_valid;
  const double sigma_cells = options.high_pass_sigma_m / grid.axial_step_m();
  const cv::Mat a = HighPassOverValid(map, map_valid, sigma_cells);
  const cv::Mat b = HighPassOverValid(albedo, albedo_valid, sigma_cells);

  DenseMapAgreement best;
  const int limit = options.max_shift_cells;
  for (int dr = -limit; dr <= limit; ++dr) {
    for (int dc = -limit; dc <= limit; ++dc) {
      double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
      int count = 0;
      for (int row = std::max(0, -dr); row < std::min(map.rows, map.rows - dr); ++row) {
        for (int col = 0; col < map.cols; ++col) {
          const int other_col = ((col + dc) % map.cols + map.cols) % map.cols;
          if (!map_valid.at<uchar>(row, col) || !albedo_valid.at<uchar>(row + dr, other_col)) {
            continue;
          }
          const double x = a.at<float>(row, col), y = b.at<float>(row + dr, other_col);
          sa += x, sb += y, saa += x * x, sbb += y * y, sab += x * y, ++count;
        }
      }
      if (count < 100) continue;
      const double spread = (saa - sa * sa / count) * (sbb - sb * sb / count);
      if (!(spread > 0)) continue;
      const double c = (sab - sa * sb / count) / std::sqrt(spread);
      if (std::isnan(best.correlation) || c > best.correlation) {
        best.correlation = c;
        best.cells = count;
        best.shift_rows = dr;
        best.shift_cols = dc;
      }
    }
  }
  best.shift_at_limit = limit > 0 && !std::isnan(best.correlation) &&
                        (std::abs(best.shift_rows) == limit || std::abs(best.shift_cols) == limit);
  return best;
}

}  // namespace pipescope
