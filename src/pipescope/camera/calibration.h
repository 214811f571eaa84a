#pragma once

// Camera calibration from views of a planar checkerboard (issue 4; 001 §II): corner detection,
// then the model's parameters and one board pose per view that minimise the sum of squared
// reprojection errors of all corners. pinhole-radtan and kannala-brandt use OpenCV's
// calibrateCamera and fisheye::calibrate; fisheye-poly (001 eq. 1) is fitted with Ceres from an
// initialisation on the view sphere, so it works for lenses past 180 degrees.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <string>
#include <utility>
#include <vector>

#include "pipescope/camera/camera.h"

namespace pipescope {

// A checkerboard described by its inner corners, as OpenCV's detectors count them.
struct CheckerboardSpec {
  int cols = 9;  // inner corners along a row (the board's x)
  int rows = 6;  // inner corners along a column (the board's y)
  double square_m = 0.025;

  int NumCorners() const { return cols * rows; }
};

// Parses "COLSxROWS" (e.g. "9x6"); throws InputError naming `flag` for anything else or for
// fewer than 2 corners either way.
CheckerboardSpec ParseCheckerboardSize(const std::string& text, const std::string& flag);

// The inner corners in the board frame, row by row: corner (c, r) at (c s, r s, 0), index
// r * cols + c. This is the order DetectCheckerboardCorners returns them in.
std::vector<Eigen::Vector3d> CheckerboardCorners(const CheckerboardSpec& board);

// Finds the board's inner corners with sub-pixel accuracy in an 8- or 16-bit, grey or colour
// image; false when the whole board is not found. cv::findChessboardCornersSB (a localised
// detector that tolerates the curvature of fisheye images) finds the board; each corner is then
// refined by the gradient-orthogonality condition of cv::cornerSubPix, evaluated without
// resampling the image, which cv::cornerSubPix does and which biases corners by up to 0.06 px
// (calibration.cc). Pixel (0, 0) is the centre of the top-left pixel, as GUIDE §3 and OpenCV
// have it.
bool DetectCheckerboardCorners(const cv::Mat& image, const CheckerboardSpec& board,
                               std::vector<Eigen::Vector2d>* corners);

// The corners found in one image.
struct CalibrationView {
  std::string name;                      // the image, for reports
  std::vector<Eigen::Vector2d> corners;  // CheckerboardCorners order
};

struct CalibrationOptions {
  // pinhole-radtan: k3 is estimated only when the corners reach this far from the optical axis
  // (degrees); below it the sixth-order term is barely observable and trades off against k1, k2
  // and the focal length, so it is held at 0 (OpenCV's advice for narrow lenses).
  double radtan_k3_min_angle_deg = 45.0;
  // Solver iterations of each stage.
  int max_iterations = 200;
  // fisheye-poly: number of k1 values tried, log-spaced, before the non-linear fit.
  int fisheye_k1_samples = 120;
};

struct CalibrationResult {
  explicit CalibrationResult(Camera fitted) : camera(std::move(fitted)) {}

  Camera camera;
  std::vector<Eigen::Isometry3d> cam_from_board;  // one per view
  std::vector<double> view_rms_px;                // one per view
  double rms_px = 0.0;  // sqrt(sum of squared corner errors / corners), as OpenCV reports it
  int num_corners = 0;
  double max_angle_deg = 0.0;  // largest angle of a corner from the fitted optical axis
  std::string method;          // what fitted it, for reports
};

// Fits `model_id` to the views (at least one) of an image of width x height. Throws InputError
// when the views are too few or the fit fails (a degenerate set of views).
CalibrationResult CalibrateCamera(CameraModelId model_id, int width, int height,
                                  const CheckerboardSpec& board,
                                  const std::vector<CalibrationView>& views,
                                  const CalibrationOptions& options = {});

// The reprojection error of each corner of a view, |projected - observed| in pixels (a corner
// that does not project counts as infinite).
std::vector<double> CornerReprojectionErrors(const Camera& camera,
                                             const Eigen::Isometry3d& cam_from_board,
                                             const CheckerboardSpec& board,
                                             const std::vector<Eigen::Vector2d>& corners);

// The pose of a planar board from unit bearings of its points, which may point anywhere on the
// view sphere (also behind the image plane). Zhang's homography written on the sphere,
// b_j x [r1 r2 t] (X_j, Y_j, 1)^T = 0, solved linearly and projected onto a rotation. False
// with fewer than 4 points or a degenerate configuration.
bool PlanarPoseFromBearings(const std::vector<Eigen::Vector3d>& points_board,
                            const std::vector<Eigen::Vector3d>& bearings,
                            Eigen::Isometry3d* cam_from_board);

}  // namespace pipescope
