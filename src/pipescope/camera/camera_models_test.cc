#include "pipescope/camera/camera_models.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <opencv2/calib3d.hpp>
#include <random>
#include <string>
#include <vector>

#include "pipescope/camera/camera.h"
#include "pipescope/util/error.h"

namespace pipescope {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDegree = kPi / 180.0;

// Realistic calibrations, one per model.
template <typename Model>
Camera TestCamera();

// EuRoC MAV cam0 (752x480) as calibrated with Kalibr, plus a small k3.
template <>
Camera TestCamera<PinholeRadtanModel>() {
  return Camera(CameraModelId::kPinholeRadtan, 752, 480,
                {458.654, 457.296, 367.215, 248.375, -0.28340811, 0.07395907, 0.00019359,
                 1.76187114e-05, -0.0012});
}

// A 640x480 fisheye with about 165 degrees across the diagonal.
template <>
Camera TestCamera<KannalaBrandtModel>() {
  return Camera(CameraModelId::kKannalaBrandt, 640, 480,
                {280.3, 279.8, 319.1, 240.6, -0.013, 0.021, -0.012, 0.0025});
}

// A 190 degree lens on the 1280x960 camera of 001 §II, its image circle (r(95 deg) ~ 437 px)
// inside the frame; the frame corners lie beyond r(pi) and have no pre-image.
Camera Fisheye190Camera() {
  return Camera(CameraModelId::kFisheyePoly, 1280, 960, {270.0, -4.0, 1.5, -0.3, 641.2, 478.9});
}
template <>
Camera TestCamera<FisheyePolyModel>() {
  return Fisheye190Camera();
}

Eigen::Vector3d BearingFromAngles(double theta, double phi) {
  return Eigen::Vector3d(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                         std::cos(theta));
}

double AngleFromAxis(const Eigen::Vector3d& point) {
  return std::atan2(point.head<2>().norm(), point.z());
}

// Pixels on a grid over the whole image, its border included.
std::vector<Eigen::Vector2d> ImageGrid(const Camera& camera, int num_x, int num_y) {
  std::vector<Eigen::Vector2d> pixels;
  for (int j = 0; j <= num_y; ++j) {
    for (int i = 0; i <= num_x; ++i) {
      pixels.emplace_back(-0.5 + camera.Width() * static_cast<double>(i) / num_x,
                          -0.5 + camera.Height() * static_cast<double>(j) / num_y);
    }
  }
  return pixels;
}

template <typename Model>
class CameraModelTest : public ::testing::Test {};

using AllModels = ::testing::Types<PinholeRadtanModel, KannalaBrandtModel, FisheyePolyModel>;
TYPED_TEST_SUITE(CameraModelTest, AllModels);

TYPED_TEST(CameraModelTest, UnprojectThenProjectCoversTheImage) {
  using Model = TypeParam;
  const Camera camera = TestCamera<Model>();
  ASSERT_EQ(camera.ModelName(), Model::kName);
  ASSERT_EQ(camera.NumParams(), Model::kNumParams);
  int num_unprojected = 0;
  int num_beyond_90_deg = 0;
  const std::vector<Eigen::Vector2d> pixels = ImageGrid(camera, 64, 48);
  for (const Eigen::Vector2d& pixel : pixels) {
    Eigen::Vector3d bearing;
    if (!camera.Unproject(pixel, &bearing)) {
      // Only fisheye-poly has pixels (the frame corners) beyond its maximum angle.
      EXPECT_EQ(Model::kId, CameraModelId::kFisheyePoly) << pixel.transpose();
      continue;
    }
    ++num_unprojected;
    EXPECT_NEAR(bearing.norm(), 1.0, 1e-12);
    EXPECT_LE(AngleFromAxis(bearing), camera.MaxAngle() + 1e-12);
    if (bearing.z() < 0.0) ++num_beyond_90_deg;

    Eigen::Vector2d reprojected;
    const ProjectionStatus status = camera.Project(bearing, &reprojected);
    EXPECT_TRUE(status == ProjectionStatus::kValid || status == ProjectionStatus::kOutsideImage)
        << ProjectionStatusName(status);
    EXPECT_LE((reprojected - pixel).norm(), 1e-6) << pixel.transpose();

    // The model's own entry point (which finds the maximum angle itself) agrees.
    Eigen::Vector3d direct;
    ASSERT_TRUE(Model::UnprojectPixel(camera.Params().data(), pixel.data(), direct.data()));
    EXPECT_LE((direct - bearing).norm(), 1e-14);
  }
  if (Model::kId == CameraModelId::kFisheyePoly) {
    EXPECT_GT(num_beyond_90_deg, 100);
    EXPECT_LT(num_unprojected, static_cast<int>(pixels.size()));
  } else {
    EXPECT_EQ(num_unprojected, static_cast<int>(pixels.size()));
  }
}

TYPED_TEST(CameraModelTest, ProjectThenUnprojectRecoversTheBearing) {
  const Camera camera = TestCamera<TypeParam>();
  std::mt19937 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  int num_valid = 0;
  for (int i = 0; i < 10000; ++i) {
    const Eigen::Vector3d bearing =
        Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
    Eigen::Vector2d pixel;
    if (camera.Project(3.7 * bearing, &pixel) != ProjectionStatus::kValid) continue;
    ++num_valid;
    Eigen::Vector3d recovered;
    ASSERT_TRUE(camera.Unproject(pixel, &recovered)) << bearing.transpose();
    EXPECT_LE((recovered - bearing).norm(), 1e-10) << bearing.transpose();
  }
  EXPECT_GT(num_valid, 1000);
}

// Central differences of the double projection, step relative to the variable.
template <typename Model>
void NumericJacobians(const std::vector<double>& params, const Eigen::Vector3d& point,
                      Eigen::Matrix<double, 2, 3>* d_point, Eigen::MatrixXd* d_params) {
  const auto project = [](const std::vector<double>& p, const Eigen::Vector3d& x) {
    Eigen::Vector2d pixel;
    Model::ProjectPoint(p.data(), x.data(), pixel.data());
    return pixel;
  };
  for (int i = 0; i < 3; ++i) {
    const double step = 1e-5 * std::max(1.0, point.norm());
    Eigen::Vector3d plus = point, minus = point;
    plus[i] += step;
    minus[i] -= step;
    d_point->col(i) = (project(params, plus) - project(params, minus)) / (2.0 * step);
  }
  d_params->resize(2, params.size());
  for (std::size_t j = 0; j < params.size(); ++j) {
    const double step = 1e-5 * std::max(1.0, std::abs(params[j]));
    std::vector<double> plus = params, minus = params;
    plus[j] += step;
    minus[j] -= step;
    d_params->col(j) = (project(plus, point) - project(minus, point)) / (2.0 * step);
  }
}

// Elementwise agreement relative to the largest entry of the row.
void ExpectRowsNear(const Eigen::MatrixXd& actual, const Eigen::MatrixXd& expected,
                    const std::string& what) {
  ASSERT_EQ(actual.rows(), expected.rows());
  ASSERT_EQ(actual.cols(), expected.cols());
  for (int r = 0; r < actual.rows(); ++r) {
    const double scale = std::max(1.0, expected.row(r).cwiseAbs().maxCoeff());
    for (int c = 0; c < actual.cols(); ++c) {
      EXPECT_NEAR(actual(r, c), expected(r, c), 1e-6 * scale)
          << what << " (" << r << "," << c << ")";
    }
  }
}

TYPED_TEST(CameraModelTest, JacobiansMatchCentralDifferences) {
  using Model = TypeParam;
  const Camera camera = TestCamera<Model>();
  // Points behind a coarse pixel grid at varied depths, plus the optical axis itself, where the
  // projections switch to their Taylor form.
  std::vector<Eigen::Vector3d> points = {Eigen::Vector3d(0.0, 0.0, 2.0),
                                         Eigen::Vector3d(1e-7, -2e-7, 1.5)};
  int index = 0;
  for (const Eigen::Vector2d& pixel : ImageGrid(camera, 8, 6)) {
    Eigen::Vector3d bearing;
    if (camera.Unproject(pixel, &bearing)) points.push_back((0.5 + 0.1 * index++) * bearing);
  }
  ASSERT_GT(points.size(), 40u);
  for (const Eigen::Vector3d& point : points) {
    Eigen::Vector2d pixel;
    Eigen::Matrix<double, 2, 3> d_point;
    Eigen::MatrixXd d_params;
    const ProjectionStatus status = camera.ProjectWithJacobians(point, &pixel, &d_point, &d_params);
    ASSERT_NE(status, ProjectionStatus::kBehindCamera);
    ASSERT_TRUE(d_point.allFinite() && d_params.allFinite()) << point.transpose();
    Eigen::Vector2d plain;
    camera.Project(point, &plain);
    EXPECT_LE((pixel - plain).norm(), 1e-9);

    Eigen::Matrix<double, 2, 3> numeric_point;
    Eigen::MatrixXd numeric_params;
    NumericJacobians<Model>(camera.Params(), point, &numeric_point, &numeric_params);
    const std::string where = "at point " + std::to_string(point.x()) + " " +
                              std::to_string(point.y()) + " " + std::to_string(point.z());
    ExpectRowsNear(d_point, numeric_point, "d_pixel_d_point " + where);
    ExpectRowsNear(d_params, numeric_params, "d_pixel_d_params " + where);
  }
}

TYPED_TEST(CameraModelTest, DispatchByIdMatchesTheModel) {
  using Model = TypeParam;
  const Camera camera = TestCamera<Model>();
  const Eigen::Vector3d point(0.3, -0.2, 1.1);
  Eigen::Vector2d direct, dispatched;
  Model::ProjectPoint(camera.Params().data(), point.data(), direct.data());
  ProjectPoint(Model::kId, camera.Params().data(), point.data(), dispatched.data());
  EXPECT_EQ(direct, dispatched);
  EXPECT_EQ(CameraModelFromName(Model::kName), Model::kId);
  EXPECT_EQ(CameraModelName(Model::kId), Model::kName);
  EXPECT_EQ(CameraModelNumParams(Model::kId), Model::kNumParams);
}

////////////////////////////////////////////////////////////////////////////////////////////////
// Agreement with OpenCV, the independent oracle for the two OpenCV models.
////////////////////////////////////////////////////////////////////////////////////////////////

std::vector<cv::Point3d> RandomPointsInFront(double max_angle, int count) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> theta(0.0, max_angle), phi(-kPi, kPi), depth(0.3, 8.0);
  std::vector<cv::Point3d> points;
  for (int i = 0; i < count; ++i) {
    const Eigen::Vector3d point = depth(rng) * BearingFromAngles(theta(rng), phi(rng));
    points.emplace_back(point.x(), point.y(), point.z());
  }
  points.emplace_back(0.0, 0.0, 1.0);  // The optical axis.
  return points;
}

TEST(PinholeRadtanModel, MatchesCvProjectPoints) {
  const Camera camera = TestCamera<PinholeRadtanModel>();
  const std::vector<double>& p = camera.Params();
  const cv::Matx33d camera_matrix(p[0], 0, p[2], 0, p[1], p[3], 0, 0, 1);
  const std::vector<double> distortion = {p[4], p[5], p[6], p[7], p[8]};
  const std::vector<cv::Point3d> points = RandomPointsInFront(50 * kDegree, 500);
  std::vector<cv::Point2d> expected;
  cv::projectPoints(points, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), camera_matrix, distortion,
                    expected);
  for (std::size_t i = 0; i < points.size(); ++i) {
    Eigen::Vector2d pixel;
    camera.Project(Eigen::Vector3d(points[i].x, points[i].y, points[i].z), &pixel);
    EXPECT_NEAR(pixel.x(), expected[i].x, 1e-6);
    EXPECT_NEAR(pixel.y(), expected[i].y, 1e-6);
  }
}

TEST(KannalaBrandtModel, MatchesCvFisheyeProjectPoints) {
  const Camera camera = TestCamera<KannalaBrandtModel>();
  const std::vector<double>& p = camera.Params();
  const cv::Matx33d camera_matrix(p[0], 0, p[2], 0, p[1], p[3], 0, 0, 1);
  const cv::Vec4d distortion(p[4], p[5], p[6], p[7]);
  const std::vector<cv::Point3d> points = RandomPointsInFront(85 * kDegree, 500);
  std::vector<cv::Point2d> expected;
  cv::fisheye::projectPoints(points, expected, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0),
                             camera_matrix, distortion);
  for (std::size_t i = 0; i < points.size(); ++i) {
    Eigen::Vector2d pixel;
    camera.Project(Eigen::Vector3d(points[i].x, points[i].y, points[i].z), &pixel);
    EXPECT_NEAR(pixel.x(), expected[i].x, 1e-6);
    EXPECT_NEAR(pixel.y(), expected[i].y, 1e-6);
  }
}

////////////////////////////////////////////////////////////////////////////////////////////////
// Validity limits
////////////////////////////////////////////////////////////////////////////////////////////////

TEST(FisheyePolyModel, Realistic190DegreeLensReachesPast95Degrees) {
  // 001 §II: 190 degrees on 1280x960; k1 ~ 410 px/rad with small higher terms.
  const Camera paper_lens(CameraModelId::kFisheyePoly, 1280, 960,
                          {410.0, -8.0, 3.0, -1.0, 640.0, 480.0});
  EXPECT_GE(paper_lens.MaxAngle(), 95 * kDegree);
  EXPECT_GE(Fisheye190Camera().MaxAngle(), 95 * kDegree);
}

TEST(FisheyePolyModel, ProjectsAndUnprojectsAt93Degrees) {
  const Camera camera = Fisheye190Camera();
  const Eigen::Vector3d bearing = BearingFromAngles(93 * kDegree, 30 * kDegree);
  ASSERT_LT(bearing.z(), 0.0);
  Eigen::Vector2d pixel;
  ASSERT_EQ(camera.Project(2.0 * bearing, &pixel), ProjectionStatus::kValid);
  // Eq. 1 directly: r(theta) along phi = 30 degrees.
  const double theta = 93 * kDegree;
  const double radius = 270.0 * theta - 4.0 * std::pow(theta, 3) + 1.5 * std::pow(theta, 4) -
                        0.3 * std::pow(theta, 5);
  EXPECT_NEAR(pixel.x(), 641.2 + radius * std::cos(30 * kDegree), 1e-9);
  EXPECT_NEAR(pixel.y(), 478.9 + radius * std::sin(30 * kDegree), 1e-9);
  Eigen::Vector3d recovered;
  ASSERT_TRUE(camera.Unproject(pixel, &recovered));
  EXPECT_LE((recovered - bearing).norm(), 1e-12);
}

// Each model with a single higher-order term whose fold has a closed form; the maximum angle
// must sit on it, unprojection must work just inside it and fail just outside.
struct FoldCase {
  Camera camera;
  double expected_max_angle;
  Eigen::Vector2d centre;
};

std::vector<FoldCase> FoldCases() {
  std::vector<FoldCase> cases;
  // radtan: d/dr [r (1 + k1 r^2)] = 1 + 3 k1 r^2 = 0.
  cases.push_back(
      {Camera(CameraModelId::kPinholeRadtan, 640, 480, {400, 400, 320, 240, -0.4, 0, 0, 0, 0}),
       std::atan(std::sqrt(1.0 / (3 * 0.4))), Eigen::Vector2d(320, 240)});
  // kannala-brandt: d/dtheta [theta (1 + k4 theta^8)] = 1 + 9 k4 theta^8 = 0.
  cases.push_back(
      {Camera(CameraModelId::kKannalaBrandt, 640, 480, {300, 300, 320, 240, 0, 0, 0, -0.1}),
       std::pow(1.0 / (9 * 0.1), 1.0 / 8.0), Eigen::Vector2d(320, 240)});
  // fisheye-poly: d/dtheta [k1 theta + k4 theta^5] = k1 + 5 k4 theta^4 = 0.
  cases.push_back({Camera(CameraModelId::kFisheyePoly, 1280, 960, {300, 0, 0, -20, 640, 480}),
                   std::pow(300.0 / (5 * 20.0), 0.25), Eigen::Vector2d(640, 480)});
  return cases;
}

TEST(CameraModels, MaxAngleIsTheFoldOfTheRadialMapping) {
  for (const FoldCase& fold : FoldCases()) {
    SCOPED_TRACE(fold.camera.ModelName());
    EXPECT_NEAR(fold.camera.MaxAngle(), fold.expected_max_angle, 1e-10);
    // Pixels along +x at angles just inside and just outside the fold.
    Eigen::Vector2d inside;
    fold.camera.Project(BearingFromAngles(fold.expected_max_angle - 1e-3, 0.0), &inside);
    Eigen::Vector3d bearing;
    ASSERT_TRUE(fold.camera.Unproject(inside, &bearing));
    EXPECT_NEAR(AngleFromAxis(bearing), fold.expected_max_angle - 1e-3, 1e-10);
    // The radial mapping peaks at the fold, so a pixel further out has no pre-image at all.
    const Eigen::Vector2d outside = inside + (inside - fold.centre).normalized();
    EXPECT_FALSE(fold.camera.Unproject(outside, &bearing));
  }
}

TEST(CameraModels, PerspectiveModelsStopShortOf90Degrees) {
  const Camera radtan(CameraModelId::kPinholeRadtan, 640, 480, {400, 400, 320, 240, 0, 0, 0, 0, 0});
  const Camera kb(CameraModelId::kKannalaBrandt, 640, 480, {300, 300, 320, 240, 0, 0, 0, 0});
  const Camera poly(CameraModelId::kFisheyePoly, 640, 480, {300, 0, 0, 0, 320, 240});
  EXPECT_NEAR(radtan.MaxAngle(), kPi / 2 - kMaxAngleMargin, 1e-12);
  EXPECT_NEAR(kb.MaxAngle(), kPi / 2 - kMaxAngleMargin, 1e-12);
  EXPECT_NEAR(poly.MaxAngle(), kPi - kMaxAngleMargin, 1e-12);
}

TEST(Camera, ProjectionStatuses) {
  const Camera radtan = TestCamera<PinholeRadtanModel>();
  const Camera kb = TestCamera<KannalaBrandtModel>();
  const Camera poly = Fisheye190Camera();
  Eigen::Vector2d pixel;

  // Behind: z <= 0 for the perspective-type models, only the zero vector for fisheye-poly.
  EXPECT_EQ(radtan.Project(Eigen::Vector3d(0.1, 0.1, -1.0), &pixel),
            ProjectionStatus::kBehindCamera);
  EXPECT_EQ(kb.Project(Eigen::Vector3d(1.0, 0.0, 0.0), &pixel), ProjectionStatus::kBehindCamera);
  EXPECT_EQ(poly.Project(Eigen::Vector3d::Zero(), &pixel), ProjectionStatus::kBehindCamera);
  EXPECT_EQ(poly.Project(Eigen::Vector3d(1.0, 0.0, 0.0), &pixel), ProjectionStatus::kValid);
  EXPECT_NEAR(pixel.x(),
              641.2 + 270.0 * kPi / 2 - 4.0 * std::pow(kPi / 2, 3) + 1.5 * std::pow(kPi / 2, 4) -
                  0.3 * std::pow(kPi / 2, 5),
              1e-9);

  // Outside the field of view: beyond the fold of a lens that folds at ~75 degrees.
  const Camera folding = FoldCases()[2].camera;
  EXPECT_EQ(folding.Project(BearingFromAngles(100 * kDegree, 0.3), &pixel),
            ProjectionStatus::kOutsideFieldOfView);
  EXPECT_EQ(folding.Project(BearingFromAngles(60 * kDegree, 0.3), &pixel),
            ProjectionStatus::kValid);

  // Outside the image: in the field of view but off the frame (the fisheye's corner region is
  // within its field of view along the diagonal beyond the image circle's vertical extent).
  EXPECT_EQ(radtan.Project(Eigen::Vector3d(2.0, 0.0, 1.0), &pixel),
            ProjectionStatus::kOutsideImage);
  EXPECT_GT(pixel.x(), radtan.Width() - 0.5);
  EXPECT_EQ(poly.Project(BearingFromAngles(120 * kDegree, kPi / 2), &pixel),
            ProjectionStatus::kOutsideImage);

  // The image covers [-0.5, w - 0.5] x [-0.5, h - 0.5].
  EXPECT_TRUE(radtan.IsInImage(Eigen::Vector2d(-0.5, -0.5)));
  EXPECT_TRUE(radtan.IsInImage(Eigen::Vector2d(751.5, 479.5)));
  EXPECT_FALSE(radtan.IsInImage(Eigen::Vector2d(-0.51, 10)));
  EXPECT_FALSE(radtan.IsInImage(Eigen::Vector2d(10, 479.51)));
}

TEST(Camera, PixelsPerRadianOnAxisIsTheFocalLengthOrK1) {
  const Camera radtan(CameraModelId::kPinholeRadtan, 640, 480,
                      {400, 380, 320, 240, -0.2, 0.05, 0.001, 0.002, 0});
  const Camera kb(CameraModelId::kKannalaBrandt, 640, 480, {300, 310, 320, 240, 0.1, 0, 0, 0});
  const Camera poly(CameraModelId::kFisheyePoly, 640, 480, {146, -1.5, 0.2, 0, 320, 240});
  EXPECT_NEAR(radtan.PixelsPerRadianOnAxis(), 400.0, 1e-4);  // the probe is 1e-6 off the axis
  EXPECT_NEAR(kb.PixelsPerRadianOnAxis(), 300.0, 1e-6);
  EXPECT_NEAR(poly.PixelsPerRadianOnAxis(), 146.0, 1e-6);
  // Against a finite difference of Project over a small angle.
  Eigen::Vector2d centre, off;
  const double angle = 1e-4;
  poly.Project(Eigen::Vector3d(0, 0, 1), &centre);
  poly.Project(Eigen::Vector3d(std::sin(angle), 0, std::cos(angle)), &off);
  EXPECT_NEAR((off - centre).norm() / angle, poly.PixelsPerRadianOnAxis(), 1e-3);
}

TEST(Camera, RejectsBadParameters) {
  try {
    Camera(CameraModelId::kPinholeRadtan, 640, 480, {400, 400, 320, 240});
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("takes 9"), std::string::npos) << error.what();
  }
  EXPECT_THROW(Camera(CameraModelId::kFisheyePoly, 0, 480, {300, 0, 0, 0, 320, 240}), InputError);
  EXPECT_THROW(Camera(CameraModelId::kFisheyePoly, 640, 480, {-300, 0, 0, 0, 320, 240}),
               InputError);
  EXPECT_THROW(Camera(CameraModelId::kKannalaBrandt, 640, 480, {300, NAN, 320, 240, 0, 0, 0, 0}),
               InputError);
}

TEST(CameraModels, UnknownNameListsTheValidOnes) {
  try {
    CameraModelFromName("omni");
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    const std::string message = error.what();
    for (const std::string name : {"omni", "pinhole-radtan", "kannala-brandt", "fisheye-poly"}) {
      EXPECT_NE(message.find(name), std::string::npos) << message;
    }
  }
}

}  // namespace
}  // namespace pipescope
