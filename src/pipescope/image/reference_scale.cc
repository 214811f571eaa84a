#include "pipescope/image/reference_scale.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <string>
#include <utility>

#include "pipescope/image/undistortion.h"
#include "pipescope/io/image_source.h"  // ToFloatGrey: ratios do not care about its 16-bit scale
#include "pipescope/util/error.h"

namespace pipescope {
namespace {

// ---- Detection --------------------------------------------------------------------------------

// The blob detector works on 8 bits with a fixed threshold ladder (50 to 220); scaling the
// maximum to 255 without an offset keeps intensity ratios, which the contrast test relies on.
cv::Mat Grey8(const cv::Mat& grey) {
  double high = 0.0;
  cv::minMaxLoc(grey, nullptr, &high);
  cv::Mat result;
  grey.convertTo(result, CV_8U, high > 0.0 ? 255.0 / high : 1.0);
  return result;
}

// Whether a dark blob looks like printed ink on the target's white card rather than a stain on
// the wall: its core must be much darker than its surround (black print on white paper reflects
// a few percent of what the paper does; rust and pits on steel are far less contrasted).
// Compares the mean of the inner half radius with the median of a ring 1.5 to 2.2 radii out.
bool IsInkOnCard(const cv::Mat& grey, const cv::KeyPoint& blob, double max_ratio) {
  const double r = 0.5 * blob.size;
  const double outer = 2.2 * r;
  double core_sum = 0.0;
  int core_count = 0;
  std::vector<float> ring;
  for (int y = std::max(0, static_cast<int>(std::floor(blob.pt.y - outer)));
       y <= std::min(grey.rows - 1, static_cast<int>(std::ceil(blob.pt.y + outer))); ++y) {
    for (int x = std::max(0, static_cast<int>(std::floor(blob.pt.x - outer)));
         x <= std::min(grey.cols - 1, static_cast<int>(std::ceil(blob.pt.x + outer))); ++x) {
      const double distance = std::hypot(x - blob.pt.x, y - blob.pt.y);
      if (distance <= 0.5 * r) {
        core_sum += grey.at<float>(y, x);
        ++core_count;
      } else if (distance >= 1.5 * r && distance <= outer) {
        ring.push_back(grey.at<float>(y, x));
      }
    }
  }
  if (core_count == 0 || ring.empty()) return false;
  std::nth_element(ring.begin(), ring.begin() + ring.size() / 2, ring.end());
  const double surround = ring[ring.size() / 2];
  return surround > 0.0 && core_sum / core_count < max_ratio * surround;
}

cv::Ptr<cv::SimpleBlobDetector> MakeDarkBlobDetector(const cv::Size& size,
                                                     const CircleGridOptions& options) {
  cv::SimpleBlobDetector::Params params;
  params.filterByColor = true;
  params.blobColor = 0;  // dark circles on a light card
  params.filterByArea = true;
  params.minArea = static_cast<float>(options.min_blob_area_px);
  params.maxArea = static_cast<float>(options.max_blob_area_fraction * size.area());
  params.filterByCircularity = true;
  params.minCircularity = static_cast<float>(options.min_circularity);
  params.filterByConvexity = true;
  params.minConvexity = 0.85f;
  params.filterByInertia = true;
  params.minInertiaRatio = 0.2f;
  return cv::SimpleBlobDetector::create(params);
}

// Least-squares plane a + b dx + c dy through the samples; false when they do not span one.
bool FitPlane(const std::vector<Eigen::Vector3d>& samples, Eigen::Vector3d* plane) {
  if (samples.size() < 8) return false;
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& s : samples) {
    const Eigen::Vector3d row(1.0, s.x(), s.y());
    normal += row * row.transpose();
    rhs += row * s.z();
  }
  const Eigen::LDLT<Eigen::Matrix3d> ldlt(normal);
  if (ldlt.info() != Eigen::Success || std::abs(normal.determinant()) < 1e-9) return false;
  *plane = ldlt.solve(rhs);
  return true;
}

// Pixels of a circle's window: offset from the window centre, intensity, and whether the
// pixel lies in the ring of white card around the circle.
struct WindowPixel {
  Eigen::Vector2i pixel;
  Eigen::Vector2d offset;
  double intensity = 0.0;
};

// Per-pixel darkness 1 - I / B of the pixels within `window` of `centre`, with B the white
// surround fitted as a plane to the pixels at least `ring_inner` out. False near the border or
// when the surround does not fit.
bool DarknessWindow(const cv::Mat& grey, const Eigen::Vector2d& centre, double window,
                    double ring_inner, double fallback_white, std::vector<WindowPixel>* pixels,
                    std::vector<double>* darkness) {
  if (centre.x() - window < 0.0 || centre.y() - window < 0.0 ||
      centre.x() + window > grey.cols - 1.0 || centre.y() + window > grey.rows - 1.0) {
    return false;
  }
  pixels->clear();
  std::vector<Eigen::Vector3d> ring;
  for (int y = static_cast<int>(std::ceil(centre.y() - window));
       y <= static_cast<int>(std::floor(centre.y() + window)); ++y) {
    for (int x = static_cast<int>(std::ceil(centre.x() - window));
         x <= static_cast<int>(std::floor(centre.x() + window)); ++x) {
      const Eigen::Vector2d offset = Eigen::Vector2d(x, y) - centre;
      const double distance = offset.norm();
      if (distance > window) continue;
      const double intensity = grey.at<float>(y, x);
      pixels->push_back({Eigen::Vector2i(x, y), offset, intensity});
      if (distance >= ring_inner) ring.emplace_back(offset.x(), offset.y(), intensity);
    }
  }
  Eigen::Vector3d plane;
  if (!FitPlane(ring, &plane)) plane = Eigen::Vector3d(fallback_white, 0.0, 0.0);
  darkness->resize(pixels->size());
  for (std::size_t i = 0; i < pixels->size(); ++i) {
    const Eigen::Vector2d& offset = (*pixels)[i].offset;
    const double background = plane[0] + plane[1] * offset.x() + plane[2] * offset.y();
    if (!(background > 0.0)) return false;
    // Background noise enters with zero mean and is not clipped, so it adds no bias.
    (*darkness)[i] = 1.0 - (*pixels)[i].intensity / background;
  }
  return true;
}

// Where `pixel` of `camera` lands in the perspective image (UndistortPoint) and how much area
// of that image one pixel covers there (1 / |det d pixel / d perspective|).
bool UndistortWithArea(const Camera& camera, const Eigen::Vector2d& pixel,
                       Eigen::Vector2d* undistorted, double* area) {
  Eigen::Vector3d bearing;
  if (!camera.Unproject(pixel, &bearing) || !(bearing.z() > 1e-9)) return false;
  const Eigen::Vector3d point = bearing / bearing.z();
  Eigen::Vector2d reprojected;
  Eigen::Matrix<double, 2, 3> d_pixel_d_point;
  if (camera.ProjectWithJacobians(point, &reprojected, &d_pixel_d_point, nullptr) ==
      ProjectionStatus::kBehindCamera) {
    return false;
  }
  const double f = CentralFocalLengthPx(camera);
  const cv::Point2d c = PrincipalPoint(camera);
  // On the plane z = 1 the perspective image is c + f (x, y), so d pixel / d perspective is
  // the x, y columns over f.
  const double determinant = d_pixel_d_point.leftCols<2>().determinant() / (f * f);
  if (!(std::abs(determinant) > 1e-12)) return false;
  *undistorted = Eigen::Vector2d(c.x + f * point.x(), c.y + f * point.y());
  *area = 1.0 / std::abs(determinant);
  return true;
}

// Refines the centre of one dark circle whose nearest neighbour lies `spacing_px` away: the
// centroid of the darkness 1 - I / B, with B the white surround fitted as a plane in a ring
// around the circle. Dividing by B removes the lighting's slope (000 §3.2: the robot's LEDs
// light the wall unevenly), and anti-aliased edge pixels count in proportion to their coverage,
// so the centroid is sub-pixel and unbiased. With a camera, `undistorted` receives the same
// centroid taken in the perspective image (each pixel at its undistorted position, weighted by
// its area there): the centroid of a circle's image moves under the lens's nonlinear mapping,
// so undistorting the distorted centroid (000 §3.3's route) is biased towards the image centre
// by about (circle radius / focal length)^2 for a fisheye. Empty when the circle is too close
// to the border or to its neighbours, or shows no contrast.
std::optional<Eigen::Vector2d> RefineCircleCentre(const cv::Mat& grey, Eigen::Vector2d centre,
                                                  double spacing_px, const Camera* camera,
                                                  Eigen::Vector2d* undistorted) {
  // First pass: the circle's radius from the area below the mid-level between the card's white
  // and the ink's black, in a disc that cannot reach the neighbours (circles are narrower than
  // their spacing).
  const double search = 0.5 * spacing_px;
  if (search < 2.0 || centre.x() - search < 0.0 || centre.y() - search < 0.0 ||
      centre.x() + search > grey.cols - 1.0 || centre.y() + search > grey.rows - 1.0) {
    return std::nullopt;
  }
  std::vector<float> values;
  std::vector<Eigen::Vector2d> positions;
  for (int y = static_cast<int>(std::ceil(centre.y() - search));
       y <= static_cast<int>(std::floor(centre.y() + search)); ++y) {
    for (int x = static_cast<int>(std::ceil(centre.x() - search));
         x <= static_cast<int>(std::floor(centre.x() + search)); ++x) {
      if ((Eigen::Vector2d(x, y) - centre).squaredNorm() > search * search) continue;
      values.push_back(grey.at<float>(y, x));
      positions.emplace_back(x, y);
    }
  }
  std::vector<float> sorted = values;
  std::sort(sorted.begin(), sorted.end());
  const float white = sorted[static_cast<std::size_t>(0.9 * (sorted.size() - 1))];
  const float black = sorted[static_cast<std::size_t>(0.03 * (sorted.size() - 1))];
  if (!(white > 0.0f) || white - black < 0.2f * white) return std::nullopt;
  const float mid = 0.5f * (white + black);
  Eigen::Vector2d dark_sum = Eigen::Vector2d::Zero();
  int dark_count = 0;
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (values[k] < mid) {
      dark_sum += positions[k];
      ++dark_count;
    }
  }
  if (dark_count < 3) return std::nullopt;
  centre = dark_sum / dark_count;
  const double radius = std::sqrt(dark_count / M_PI);

  // The window holds the circle and a ring of white card, but stays clear of the neighbours.
  const double window = std::min(radius + std::max(3.0, 0.6 * radius), spacing_px - radius - 1.5);
  const double ring_inner = radius + 1.5 + 0.1 * radius;
  if (window < ring_inner + 1.0) return std::nullopt;
  std::vector<WindowPixel> pixels;
  std::vector<double> darkness;
  for (int iteration = 0; iteration < 5; ++iteration) {
    if (!DarknessWindow(grey, centre, window, ring_inner, white, &pixels, &darkness)) {
      return std::nullopt;
    }
    Eigen::Vector2d weighted = Eigen::Vector2d::Zero();
    double weight_sum = 0.0;
    for (std::size_t i = 0; i < pixels.size(); ++i) {
      weighted += darkness[i] * pixels[i].offset;
      weight_sum += darkness[i];
    }
    if (!(weight_sum > 0.25 * dark_count)) return std::nullopt;
    const Eigen::Vector2d step = weighted / weight_sum;
    centre += step;
    if (step.norm() < 1e-4) break;
  }
  if (camera == nullptr) return centre;

  if (!DarknessWindow(grey, centre, window, ring_inner, white, &pixels, &darkness)) {
    return std::nullopt;
  }
  Eigen::Vector2d weighted = Eigen::Vector2d::Zero();
  double weight_sum = 0.0;
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    Eigen::Vector2d position;
    double area = 0.0;
    if (!UndistortWithArea(*camera, pixels[i].pixel.cast<double>(), &position, &area)) {
      return std::nullopt;
    }
    weighted += darkness[i] * area * position;
    weight_sum += darkness[i] * area;
  }
  if (!(std::abs(weight_sum) > 0.0)) return std::nullopt;
  *undistorted = weighted / weight_sum;
  return centre;
}

// Nearest distance from circle `index` to its grid neighbours, pixels.
double NeighbourSpacing(const std::vector<Eigen::Vector2d>& centres, int cols, int rows,
                        int index) {
  const int col = index % cols;
  const int row = index / cols;
  double spacing = std::numeric_limits<double>::infinity();
  for (const auto& [dc, dr] : {std::pair{-1, 0}, {1, 0}, {0, -1}, {0, 1}}) {
    const int c = col + dc;
    const int r = row + dr;
    if (c < 0 || c >= cols || r < 0 || r >= rows) continue;
    spacing = std::min(spacing, (centres[r * cols + c] - centres[index]).norm());
  }
  return spacing;
}

// ---- Scale fit --------------------------------------------------------------------------------

struct Monomial {
  int p = 0;  // power of u (along a row)
  int q = 0;  // power of v (across rows)
};

std::vector<Monomial> Monomials(int max_degree, int cols, int rows) {
  std::vector<Monomial> monomials;
  for (int degree = 0; degree <= max_degree; ++degree) {
    for (int q = 0; q <= degree; ++q) {
      const int p = degree - q;
      // A grid with n distinct positions along a direction supports powers below n there.
      if (p < cols && q < rows) monomials.push_back({p, q});
    }
  }
  return monomials;
}

double Power(double base, int exponent) { return exponent == 0 ? 1.0 : std::pow(base, exponent); }

// Values and u, v derivatives of the monomials at (u, v).
void EvaluateMonomials(const std::vector<Monomial>& monomials, double u, double v,
                       Eigen::VectorXd* value, Eigen::VectorXd* d_u, Eigen::VectorXd* d_v) {
  const int k = static_cast<int>(monomials.size());
  value->resize(k);
  d_u->resize(k);
  d_v->resize(k);
  for (int i = 0; i < k; ++i) {
    const auto [p, q] = monomials[i];
    (*value)[i] = Power(u, p) * Power(v, q);
    (*d_u)[i] = p == 0 ? 0.0 : p * Power(u, p - 1) * Power(v, q);
    (*d_v)[i] = q == 0 ? 0.0 : q * Power(u, p) * Power(v, q - 1);
  }
}

}  // namespace

std::optional<std::vector<Eigen::Vector2d>> DetectCircleGrid(const cv::Mat& image, int cols,
                                                             int rows,
                                                             const CircleGridOptions& options) {
  if (image.empty() || cols < 2 || rows < 2) return std::nullopt;
  const cv::Mat grey = ToFloatGrey(image);
  const cv::Ptr<cv::SimpleBlobDetector> detector = MakeDarkBlobDetector(grey.size(), options);
  std::vector<cv::KeyPoint> blobs;
  detector->detect(Grey8(grey), blobs);
  // The wall's texture yields hundreds of dark blobs, too many for the grid finder; only ink on
  // the card goes on.
  std::vector<cv::Point2f> candidates;
  for (const cv::KeyPoint& blob : blobs) {
    if (IsInkOnCard(grey, blob, options.max_ink_to_card_ratio)) candidates.push_back(blob.pt);
  }
  if (candidates.size() < static_cast<std::size_t>(cols * rows)) return std::nullopt;
  std::vector<cv::Point2f> found;
  const cv::Size pattern(cols, rows);
  // With no detector, findCirclesGrid takes the candidate points as given.
  bool ok = cv::findCirclesGrid(candidates, pattern, found, cv::CALIB_CB_SYMMETRIC_GRID,
                                cv::Ptr<cv::FeatureDetector>());
  if (!ok) {
    ok = cv::findCirclesGrid(candidates, pattern, found,
                             cv::CALIB_CB_SYMMETRIC_GRID | cv::CALIB_CB_CLUSTERING,
                             cv::Ptr<cv::FeatureDetector>());
  }
  if (!ok || found.size() != static_cast<std::size_t>(cols * rows)) return std::nullopt;

  std::vector<Eigen::Vector2d> centres;
  centres.reserve(found.size());
  for (const cv::Point2f& point : found) centres.emplace_back(point.x, point.y);
  if (!options.refine_centroids) return centres;
  std::vector<Eigen::Vector2d> refined = centres;
  for (int index = 0; index < cols * rows; ++index) {
    const double spacing = NeighbourSpacing(centres, cols, rows, index);
    const std::optional<Eigen::Vector2d> centre =
        RefineCircleCentre(grey, centres[index], spacing, nullptr, nullptr);
    if (centre && (*centre - centres[index]).norm() < 0.25 * spacing) refined[index] = *centre;
  }
  return refined;
}

std::optional<std::vector<Eigen::Vector2d>> UndistortedCircleCentroids(
    const cv::Mat& image, const Camera& camera, const std::vector<Eigen::Vector2d>& centres,
    int cols, int rows) {
  if (centres.size() != static_cast<std::size_t>(cols * rows)) {
    throw std::invalid_argument("UndistortedCircleCentroids: centre count does not match grid");
  }
  const cv::Mat grey = ToFloatGrey(image);
  std::vector<Eigen::Vector2d> undistorted(centres.size());
  for (int index = 0; index < cols * rows; ++index) {
    const double spacing = NeighbourSpacing(centres, cols, rows, index);
    const std::optional<Eigen::Vector2d> centre =
        RefineCircleCentre(grey, centres[index], spacing, &camera, &undistorted[index]);
    // Circles the centroid cannot measure keep their detected centre, undistorted.
    if (!centre || (*centre - centres[index]).norm() >= 0.25 * spacing) {
      if (!UndistortPoint(camera, centres[index], &undistorted[index])) return std::nullopt;
    }
  }
  return undistorted;
}

bool UndistortPoint(const Camera& camera, const Eigen::Vector2d& pixel,
                    Eigen::Vector2d* undistorted) {
  Eigen::Vector3d bearing;
  if (!camera.Unproject(pixel, &bearing) || !(bearing.z() > 1e-9)) return false;
  const double f = CentralFocalLengthPx(camera);
  const cv::Point2d c = PrincipalPoint(camera);
  *undistorted =
      Eigen::Vector2d(c.x + f * bearing.x() / bearing.z(), c.y + f * bearing.y() / bearing.z());
  return true;
}

ReferenceScale EstimateReferenceScale(const std::vector<Eigen::Vector2d>& undistorted_centres,
                                      int cols, int rows, double spacing_m,
                                      const Eigen::Vector2d& principal_point,
                                      const ReferenceScaleOptions& options) {
  if (cols < 2 || rows < 2) throw std::invalid_argument("EstimateReferenceScale: grid under 2x2");
  if (undistorted_centres.size() != static_cast<std::size_t>(cols * rows)) {
    throw std::invalid_argument("EstimateReferenceScale: centre count does not match the grid");
  }
  if (!(spacing_m > 0.0)) throw std::invalid_argument("EstimateReferenceScale: spacing <= 0");
  const int n = cols * rows;
  // Grid coordinates in spacings, centred on the grid for a well-conditioned fit.
  const double u0 = 0.5 * (cols - 1);
  const double v0 = 0.5 * (rows - 1);
  const std::vector<Monomial> monomials = Monomials(std::max(1, options.max_degree), cols, rows);
  const int k = static_cast<int>(monomials.size());
  Eigen::MatrixXd design(n, k);
  Eigen::MatrixXd targets(n, 2);
  Eigen::VectorXd value, d_u, d_v;
  for (int i = 0; i < n; ++i) {
    EvaluateMonomials(monomials, i % cols - u0, i / cols - v0, &value, &d_u, &d_v);
    design.row(i) = value.transpose();
    targets.row(i) = undistorted_centres[i].transpose();
  }
  const Eigen::MatrixXd normal = design.transpose() * design;
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(normal);
  const Eigen::MatrixXd coefficients = ldlt.solve(design.transpose() * targets);  // k x 2
  const Eigen::MatrixXd residuals = design * coefficients - targets;

  ReferenceScale result;
  result.fit_rms_px = std::sqrt(residuals.squaredNorm() / n);

  // The grid point imaged at the principal point: Newton on the fitted map, from the nearest
  // centre.
  int nearest = 0;
  for (int i = 1; i < n; ++i) {
    if ((undistorted_centres[i] - principal_point).squaredNorm() <
        (undistorted_centres[nearest] - principal_point).squaredNorm()) {
      nearest = i;
    }
  }
  Eigen::Vector2d uv(nearest % cols - u0, nearest / cols - v0);
  Eigen::Matrix2d jacobian;
  bool converged = false;
  for (int iteration = 0; iteration < 50; ++iteration) {
    EvaluateMonomials(monomials, uv.x(), uv.y(), &value, &d_u, &d_v);
    const Eigen::Vector2d error = principal_point - coefficients.transpose() * value;
    jacobian.col(0) = coefficients.transpose() * d_u;
    jacobian.col(1) = coefficients.transpose() * d_v;
    if (error.norm() < 1e-9) {
      converged = true;
      break;
    }
    if (std::abs(jacobian.determinant()) < 1e-12) break;
    Eigen::Vector2d step = jacobian.inverse() * error;
    if (step.norm() > 1.0) step /= step.norm();  // one spacing at a time
    uv += step;
    // A cubic extrapolated this far from its data means nothing.
    if (std::abs(uv.x()) > u0 + 3.0 || std::abs(uv.y()) > v0 + 3.0) break;
  }
  if (!converged) {
    throw InputError("the principal point (" + std::to_string(principal_point.x()) + ", " +
                     std::to_string(principal_point.y()) +
                     ") lies too far off the circle grid to extrapolate the scale there; image "
                     "the target at the image centre (000 §3.3)");
  }
  result.principal_point_on_grid = uv + Eigen::Vector2d(u0, v0);
  result.principal_point_on_target = std::abs(uv.x()) <= u0 + 0.5 && std::abs(uv.y()) <= v0 + 0.5;

  // Image x is the pipe axis (000 eq. 18): take the grid direction that runs closer to it.
  const double u_alignment = std::abs(jacobian(0, 0)) / jacobian.col(0).norm();
  const double v_alignment = std::abs(jacobian(0, 1)) / jacobian.col(1).norm();
  const bool axis_is_u = u_alignment >= v_alignment;
  const Eigen::Vector2d along = axis_is_u ? jacobian.col(0) : jacobian.col(1);
  const Eigen::Vector2d across = axis_is_u ? jacobian.col(1) : jacobian.col(0);
  result.px_per_m = along.norm() / spacing_m;
  result.across_px_per_m = across.norm() / spacing_m;

  // Standard error: residual variance pooled over both coordinates, propagated linearly through
  // the derivative (the uncertainty of the point itself is second order).
  const int dof = 2 * (n - k);
  if (dof > 0) {
    const double sigma2 = residuals.squaredNorm() / dof;
    const Eigen::VectorXd& gradient = axis_is_u ? d_u : d_v;
    const double factor = gradient.dot(ldlt.solve(gradient));
    result.std_error_px_per_m = std::sqrt(std::max(0.0, sigma2 * factor)) / spacing_m;
  }

  // The paper's mean over neighbouring pairs along the axis, for comparison.
  std::vector<double> ratios;
  for (int row = 0; row < rows; ++row) {
    for (int col = 0; col < cols; ++col) {
      const int next_col = axis_is_u ? col + 1 : col;
      const int next_row = axis_is_u ? row : row + 1;
      if (next_col >= cols || next_row >= rows) continue;
      ratios.push_back(
          (undistorted_centres[next_row * cols + next_col] - undistorted_centres[row * cols + col])
              .norm() /
          spacing_m);
    }
  }
  double sum = 0.0;
  for (const double ratio : ratios) sum += ratio;
  result.neighbour_pairs = static_cast<int>(ratios.size());
  result.mean_spacing_px_per_m = sum / ratios.size();
  double squares = 0.0;
  for (const double ratio : ratios) {
    squares += (ratio - result.mean_spacing_px_per_m) * (ratio - result.mean_spacing_px_per_m);
  }
  result.spacing_std_px_per_m = ratios.size() > 1 ? std::sqrt(squares / (ratios.size() - 1)) : 0;
  return result;
}

}  // namespace pipescope
