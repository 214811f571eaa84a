#include "pipescope/camera/calibration.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

TEST(Calibration, ParsesBoardSizes) {
  const CheckerboardSpec board = ParseCheckerboardSize("9x6", "--board");
  EXPECT_EQ(board.cols, 9);
  EXPECT_EQ(board.rows, 6);
  EXPECT_EQ(ParseCheckerboardSize("7X5", "--board").NumCorners(), 35);
  EXPECT_NE(InputErrorMessage([] { ParseCheckerboardSize("9*6", "--board"); }).find("--board"),
            std::string::npos);
  EXPECT_NE(InputErrorMessage([] { ParseCheckerboardSize("1x6", "--board"); }).find("2x2"),
            std::string::npos);
}

TEST(Calibration, CornersAreRowMajorOnTheBoardPlane) {
  const CheckerboardSpec board{4, 3, 0.03};
  const std::vector<Eigen::Vector3d> corners = CheckerboardCorners(board);
  ASSERT_EQ(corners.size(), 12u);
  EXPECT_TRUE(corners[1].isApprox(Eigen::Vector3d(0.03, 0.0, 0.0)));
  EXPECT_TRUE(corners[4].isApprox(Eigen::Vector3d(0.0, 0.03, 0.0)));
  EXPECT_TRUE(corners[11].isApprox(Eigen::Vector3d(0.09, 0.06, 0.0)));
}

Eigen::Isometry3d BoardFacingCamera(const Eigen::Vector3d& direction, double distance,
                                    double tilt_deg, const CheckerboardSpec& board) {
  const Eigen::Vector3d z = direction.normalized();
  const Eigen::Vector3d reference =
      std::abs(z.y()) < 0.9 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitX();
  Eigen::Matrix3d rotation;
  rotation.col(0) = reference.cross(z).normalized();
  rotation.col(1) = z.cross(rotation.col(0));
  rotation.col(2) = z;
  rotation = Eigen::AngleAxisd(tilt_deg * kDegToRad, rotation.col(0)).toRotationMatrix() * rotation;
  const Eigen::Vector3d centre(0.5 * (board.cols - 1) * board.square_m,
                               0.5 * (board.rows - 1) * board.square_m, 0.0);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = rotation;
  pose.translation() = distance * z - rotation * centre;
  return pose;
}

// Oracle: exact bearings of a known pose, in front of and behind the image plane.
TEST(Calibration, PlanarPoseFromBearingsIsExactAllRoundTheSphere) {
  const CheckerboardSpec board{9, 6, 0.025};
  const std::vector<Eigen::Vector3d> points = CheckerboardCorners(board);
  for (const double angle_deg : {0.0, 40.0, 89.0, 100.0, 150.0}) {
    SCOPED_TRACE(angle_deg);
    const double angle = angle_deg * kDegToRad;
    const Eigen::Isometry3d truth = BoardFacingCamera(
        Eigen::Vector3d(std::sin(angle), 0.3 * std::sin(angle), std::cos(angle)), 0.4, 30.0, board);
    std::vector<Eigen::Vector3d> bearings;
    for (const Eigen::Vector3d& point : points) bearings.push_back((truth * point).normalized());
    Eigen::Isometry3d estimate;
    ASSERT_TRUE(PlanarPoseFromBearings(points, bearings, &estimate));
    EXPECT_LT((estimate.rotation() - truth.rotation()).norm(), 1e-9);
    EXPECT_LT((estimate.translation() - truth.translation()).norm(), 1e-9);
  }
  Eigen::Isometry3d unused;
  EXPECT_FALSE(PlanarPoseFromBearings(
      {points.begin(), points.begin() + 3},
      {Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitZ()}, &unused));
}

// Views of a board projected exactly through `truth` (`exact`) plus Gaussian corner noise:
// boards over a grid of directions up to `max_angle_deg` from the axis, tilted 35 degrees about
// axes that turn from view to view.
std::vector<CalibrationView> SyntheticViews(const Camera& truth, const CheckerboardSpec& board,
                                            double max_angle_deg, double distance, double noise_px,
                                            std::vector<std::vector<Eigen::Vector2d>>* exact) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, noise_px);
  std::vector<CalibrationView> views;
  exact->clear();
  int index = 0;
  for (double angle_deg = 0.0; angle_deg <= max_angle_deg + 1e-9; angle_deg += max_angle_deg / 3) {
    for (int azimuth = 0; azimuth < (angle_deg == 0.0 ? 2 : 6); ++azimuth) {
      const double a = angle_deg * kDegToRad;
      const double phi = azimuth * M_PI / 3.0 + 0.2;
      const Eigen::Vector3d direction(std::sin(a) * std::cos(phi), std::sin(a) * std::sin(phi),
                                      std::cos(a));
      Eigen::Isometry3d pose = BoardFacingCamera(direction, distance, 35.0, board);
      // Turn the board about its viewing direction, so the tilt axis turns too.
      const Eigen::Vector3d centre =
          pose * Eigen::Vector3d(0.5 * (board.cols - 1) * board.square_m,
                                 0.5 * (board.rows - 1) * board.square_m, 0.0);
      const Eigen::Matrix3d spin =
          Eigen::AngleAxisd(1.1 * index, direction.normalized()).toRotationMatrix();
      pose.linear() = spin * pose.linear();
      pose.translation() = spin * (pose.translation() - centre) + centre;
      CalibrationView view;
      view.name = "view" + std::to_string(index++);
      std::vector<Eigen::Vector2d> pixels;
      bool usable = true;
      for (const Eigen::Vector3d& point : CheckerboardCorners(board)) {
        Eigen::Vector2d pixel;
        usable = usable && truth.Project(pose * point, &pixel) == ProjectionStatus::kValid;
        pixels.push_back(pixel);
        view.corners.push_back(pixel + Eigen::Vector2d(noise(rng), noise(rng)));
      }
      if (usable) {
        views.push_back(view);
        exact->push_back(pixels);
      }
    }
  }
  return views;
}

struct SyntheticCase {
  Camera truth;
  double max_angle_deg;
  double distance;
};

// The fit returns the true camera from noisy exact corners: the numbers without rendering or
// detection in the way. The fisheye-poly case is a 200-degree lens with boards centred up to
// 80 degrees off the axis, so its corners reach past 90.
TEST(Calibration, RecoversEveryModelFromNoisyCorners) {
  const CheckerboardSpec board{9, 6, 0.025};
  const std::vector<SyntheticCase> cases = {
      {Camera(CameraModelId::kPinholeRadtan, 640, 480,
              {500.0, 502.0, 322.0, 236.0, -0.2, 0.05, 0.001, -0.0005, 0.0}),
       28.0, 0.5},
      {Camera(CameraModelId::kKannalaBrandt, 640, 480,
              {300.0, 301.0, 318.0, 243.0, -0.01, 0.005, -0.002, 0.0005}),
       45.0, 0.45},
      {Camera(CameraModelId::kFisheyePoly, 800, 600, {170.0, -3.0, 1.0, -0.2, 401.5, 297.0}), 80.0,
       0.35},
  };
  for (const SyntheticCase& c : cases) {
    SCOPED_TRACE(c.truth.ModelName());
    std::vector<std::vector<Eigen::Vector2d>> exact;
    const std::vector<CalibrationView> views =
        SyntheticViews(c.truth, board, c.max_angle_deg, c.distance, 0.05, &exact);
    ASSERT_GE(views.size(), 12u);
    const CalibrationResult result =
        CalibrateCamera(c.truth.ModelId(), c.truth.Width(), c.truth.Height(), board, views);
    const std::vector<double>& p = result.camera.Params();
    const std::vector<double>& t = c.truth.Params();
    EXPECT_LT(std::abs(p[0] / t[0] - 1.0), 0.002);
    const int pp = c.truth.ModelId() == CameraModelId::kFisheyePoly ? 4 : 2;
    EXPECT_LT(std::hypot(p[pp] - t[pp], p[pp + 1] - t[pp + 1]), 0.5);
    // Noise of 0.05 px a coordinate is 0.0707 px a corner; the fit absorbs a few per cent.
    EXPECT_NEAR(result.rms_px, 0.05 * std::sqrt(2.0), 0.01);
    ASSERT_EQ(result.view_rms_px.size(), views.size());
    // The fitted camera and poses put every corner where the noise-free truth has it, to well
    // within the noise.
    double worst = 0.0;
    for (std::size_t v = 0; v < views.size(); ++v) {
      const std::vector<Eigen::Vector2d> no_noise = exact[v];
      std::vector<double> errors =
          CornerReprojectionErrors(result.camera, result.cam_from_board[v], board, no_noise);
      worst = std::max(worst, *std::max_element(errors.begin(), errors.end()));
    }
    EXPECT_LT(worst, 0.1);
    std::printf("%s: %zu views, rms %.4f px, worst %.4f px, focal %.5f %%, pp %.3f px\n",
                c.truth.ModelName().c_str(), views.size(), result.rms_px, worst,
                100 * std::abs(p[0] / t[0] - 1.0),
                std::hypot(p[pp] - t[pp], p[pp + 1] - t[pp + 1]));
    if (c.truth.ModelId() == CameraModelId::kFisheyePoly) {
      EXPECT_GT(result.max_angle_deg, 90.0);
    }
  }
}

TEST(Calibration, RejectsMissingViewsAndWrongCornerCounts) {
  const CheckerboardSpec board{9, 6, 0.025};
  EXPECT_NE(InputErrorMessage([&] {
              CalibrateCamera(CameraModelId::kPinholeRadtan, 640, 480, board, {});
            }).find("at least one view"),
            std::string::npos);
  CalibrationView short_view{"short.png", std::vector<Eigen::Vector2d>(10)};
  EXPECT_NE(InputErrorMessage([&] {
              CalibrateCamera(CameraModelId::kFisheyePoly, 640, 480, board, {short_view});
            }).find("short.png"),
            std::string::npos);
}

}  // namespace
}  // namespace pipescope
