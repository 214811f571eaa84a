#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "pipescope/camera/camera.h"

namespace pipescope {

// The reference scale of 000 §3.3: a target of circles fixed to the pipe wall is imaged, the
// circle centroids are mapped to the undistorted perspective image the dense methods register
// (000 §4), and the known metric spacing turns their pixel spacing into zeta, pixels per metre.

struct CircleGridOptions {
  // Blob sizes the detector accepts: at least this many pixels, at most this fraction of the
  // image.
  double min_blob_area_px = 8.0;
  double max_blob_area_fraction = 0.1;
  // Circles seen obliquely or through a fisheye are ellipses; 0.6 still rejects long stains.
  double min_circularity = 0.6;
  // A blob counts as a target circle only when its core is at most this fraction of its
  // surround's brightness: black print on white paper is near 0.05, the wall's stains and pits
  // far above, so texture around the card does not reach the grid finder.
  double max_ink_to_card_ratio = 0.4;
  // Replace the blob detector's centres (means of thresholded contours) by the centroid of each
  // circle's darkness relative to its locally fitted white surround: sub-pixel, unaffected by
  // the lighting's slope across the circle, and exact for anti-aliased edges.
  bool refine_centroids = true;
};

// Finds a symmetric grid of dark circles on a light card (cv::findCirclesGrid with a blob
// detector for dark blobs) and returns the circle centroids in pixels of `image`, row by row
// with `cols` per row; empty when no such grid is found. `image`: 8- or 16-bit or float, grey
// or colour.
std::optional<std::vector<Eigen::Vector2d>> DetectCircleGrid(const cv::Mat& image, int cols,
                                                             int rows,
                                                             const CircleGridOptions& options = {});

// Maps a pixel of `camera` to the undistorted perspective image (focal length
// CentralFocalLengthPx, the camera's principal point: the image Undistorter produces). False
// when the camera cannot unproject the pixel or its ray does not reach the perspective image
// plane (90 degrees or more off the axis).
bool UndistortPoint(const Camera& camera, const Eigen::Vector2d& pixel,
                    Eigen::Vector2d* undistorted);

// The circle centroids of a detected grid (DetectCircleGrid, row by row) taken in the
// undistorted perspective image: each pixel of a circle counts at its undistorted position,
// weighted by its area there. Undistorting a centroid measured in the distorted image, as
// 000 §3.3 does, shifts it towards the image centre by about (circle radius / focal length)^2
// of its distance from the centre, which biases zeta low by that fraction (0.06 % for 4 mm
// circles seen through a 70 degree Kannala-Brandt lens in a 6-inch pipe, docs/reference_scale.md).
// Circles whose centroid cannot be measured (at the border, no contrast) keep their detected
// centre, undistorted. Empty when a centre lies outside the perspective view (UndistortPoint).
std::optional<std::vector<Eigen::Vector2d>> UndistortedCircleCentroids(
    const cv::Mat& image, const Camera& camera, const std::vector<Eigen::Vector2d>& centres,
    int cols, int rows);

struct ReferenceScaleOptions {
  // Total degree of the polynomial map fitted from grid coordinates to undistorted pixels. The
  // wall's curvature makes the scale vary across the target: for a camera on the pipe axis, a
  // wall point at angle phi round the pipe from the image centre images at
  // x = f h / (r cos phi), y = f tan phi, so along the axis the scale grows as
  // 1 / cos phi = 1 + phi^2 / 2 (an h phi^2 term) and around it as 1 / cos^2 phi; degree 3
  // holds both to third order. Lower only for grids too small to support it (monomials u^p v^q
  // need p < cols and q < rows; that restriction is applied automatically).
  int max_degree = 3;
};

struct ReferenceScale {
  // zeta (000 §3.3): pixels per metre along image x (the pipe axis for the wall-looking camera,
  // 000 eq. 18) at the principal point of the undistorted image, the point whose motion the
  // dense methods convert (eq. 19). The derivative there of the fitted grid-to-image map.
  double px_per_m = 0.0;
  // Standard error of px_per_m from the fit's residuals; 0 when the fit has no redundancy.
  double std_error_px_per_m = 0.0;
  // The same derivative along image y (around the pipe). Equal to px_per_m for a camera looking
  // squarely at the wall; their ratio shows a tilted view.
  double across_px_per_m = 0.0;
  // The paper's plain estimate for comparison: the mean over neighbouring centres along image x
  // of pixel distance / spacing, and the standard deviation of those ratios (their spread comes
  // from the wall's curvature and the view, not noise).
  double mean_spacing_px_per_m = 0.0;
  double spacing_std_px_per_m = 0.0;
  int neighbour_pairs = 0;
  // RMS distance between the centres and the fitted map, pixels.
  double fit_rms_px = 0.0;
  // Where the principal point falls on the target, in spacings from the first circle along the
  // grid's two directions (cols, rows as ordered by the detector).
  Eigen::Vector2d principal_point_on_grid = Eigen::Vector2d::Zero();
  // False when the principal point lies more than half a spacing outside the grid, so zeta is
  // extrapolated.
  bool principal_point_on_target = false;
};

// Estimates zeta from the undistorted centres of a cols x rows grid (row by row, `cols` per
// row) whose neighbours lie `spacing_m` apart on the wall, at `principal_point` of the
// undistorted image. Throws std::invalid_argument for a wrong count, a grid under 2 x 2 or a
// non-positive spacing, and InputError when the principal point is too far off the target for
// the fitted map to reach it.
ReferenceScale EstimateReferenceScale(const std::vector<Eigen::Vector2d>& undistorted_centres,
                                      int cols, int rows, double spacing_m,
                                      const Eigen::Vector2d& principal_point,
                                      const ReferenceScaleOptions& options = {});

}  // namespace pipescope
