// The tubular EKF (004 §2) against closed forms, finite differences and synthetic tubes whose
// wall points are exact.
#include "pipescope/estimation/tubular_ekf.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

namespace pipescope {
namespace {

Camera ForwardCamera() {
  return Camera(CameraModelId::kPinholeRadtan, 640, 480,
                {320.0, 320.0, 319.5, 239.5, 0.0, 0.0, 0.0, 0.0, 0.0});
}

Eigen::Isometry3d Pose(const Eigen::Vector3d& position, const Eigen::Quaterniond& rotation) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = rotation.toRotationMatrix();
  pose.translation() = position;
  return pose;
}

// A camera looking along `tangent` (z) with its y axis as close to `down` as it goes.
Eigen::Quaterniond LookAlong(const Eigen::Vector3d& tangent, const Eigen::Vector3d& down) {
  const Eigen::Vector3d z = tangent.normalized();
  const Eigen::Vector3d y = (down - down.dot(z) * z).normalized();
  Eigen::Matrix3d r;
  r << y.cross(z), y, z;
  return Eigen::Quaterniond(r);
}

TEST(TubularEkf, PredictionFollowsConstantVelocityInClosedForm) {
  const Camera camera = ForwardCamera();
  TubularEkfOptions options;
  options.linear_acceleration_sigma = 0.3;
  TubularEkf filter(camera, Eigen::Isometry3d::Identity(), Eigen::Vector3d::UnitZ(), 0.1, options);
  Eigen::VectorXd delta = Eigen::VectorXd::Zero(filter.StateSize());
  const Eigen::Vector3d velocity(0.01, -0.02, 0.05);
  const Eigen::Vector3d angular(0.1, 0.2, -0.3);
  delta.segment<3>(TubularEkf::kVelocity) = velocity;
  delta.segment<3>(TubularEkf::kAngularVelocity) = angular;
  filter.Inject(delta);
  const double sigma_v = options.initial_speed_sigma;
  const double dt = 0.1;
  for (int step = 0; step < 5; ++step) filter.Predict(dt);
  // 004 eq. 6 integrated: r = v t, q = Exp(w t) for a body-frame w held constant.
  const Eigen::Isometry3d pose = filter.WorldFromCam();
  EXPECT_LT((pose.translation() - velocity * 0.5).norm(), 1e-12);
  const Eigen::Quaterniond expected(Eigen::AngleAxisd(angular.norm() * 0.5, angular.normalized()));
  EXPECT_LT(Eigen::Quaterniond(pose.rotation()).angularDistance(expected), 1e-9);
  // Position variance after n steps from Var(v) = s^2 and impulses V_j ~ N(0, (a dt)^2) that
  // enter as dr += V dt + later steps' dt: Var(r_x) = (n dt)^2 s^2 + (a dt)^2 dt^2 sum_j j^2.
  const int n = 5;
  double impulse_sum = 0.0;
  for (int j = 1; j <= n; ++j) impulse_sum += j * j;
  const double a = options.linear_acceleration_sigma * dt;
  const double expected_variance =
      std::pow(n * dt * sigma_v, 2) + a * a * dt * dt * impulse_sum + 1e-12;
  EXPECT_NEAR(filter.Covariance()(0, 0), expected_variance, 1e-9 * expected_variance);
  // The clone holds the pose before the last step, with that step's covariance.
  EXPECT_NEAR(filter.Covariance()(TubularEkf::kPreviousPosition, TubularEkf::kPreviousPosition),
              std::pow(4 * dt * sigma_v, 2) + a * a * dt * dt * (1 + 4 + 9 + 16) + 1e-12, 1e-12);
}

// Straight (curvature exactly 0, where the torus' derivatives must still come out) and bending
// (a bend of 4 radii).
class TubularEkfJacobian : public ::testing::TestWithParam<double> {};

TEST_P(TubularEkfJacobian, ObservationJacobianMatchesFiniteDifferences) {
  const Camera camera = ForwardCamera();
  TubularEkf filter(camera, Eigen::Isometry3d::Identity(), Eigen::Vector3d::UnitZ(), 0.1, {});
  // A state away from every special value: moving, turning, the section tilted and offset.
  Eigen::VectorXd delta = Eigen::VectorXd::Zero(filter.StateSize());
  delta.segment<3>(TubularEkf::kVelocity) << 0.004, -0.003, 0.05;
  delta.segment<3>(TubularEkf::kAngularVelocity) << 0.05, -0.08, 0.1;
  const double curvature = GetParam();
  delta.segment<7>(TubularEkf::kCameraSize) << 0.01, -0.006, 0.03, -0.02, 0.05, 0.6 * curvature,
      -0.8 * curvature;
  filter.Inject(delta);
  ASSERT_NEAR(filter.Sections()[0].geometry.curvature.norm(), curvature, 0.01);
  filter.Predict(1.0 / 15.0);
  const int n = filter.StateSize();
  int checked = 0;
  for (double u : {60.0, 200.0, 420.0, 600.0}) {
    for (double v : {40.0, 240.0, 430.0}) {
      Eigen::Vector3d bearing;
      ASSERT_TRUE(camera.Unproject(Eigen::Vector2d(u, v), &bearing));
      Eigen::Vector2d pixel;
      Eigen::MatrixXd analytic;
      if (!filter.PredictPixel(bearing, &pixel, &analytic)) continue;
      for (int j = 0; j < n; ++j) {
        const double h = 1e-6;
        TubularEkf plus = filter, minus = filter;
        Eigen::VectorXd step = Eigen::VectorXd::Zero(n);
        step[j] = h;
        plus.Inject(step);
        minus.Inject(-step);
        Eigen::Vector2d p_plus, p_minus;
        ASSERT_TRUE(plus.PredictPixel(bearing, &p_plus, nullptr));
        ASSERT_TRUE(minus.PredictPixel(bearing, &p_minus, nullptr));
        const Eigen::Vector2d numeric = (p_plus - p_minus) / (2.0 * h);
        const double scale = std::max(1.0, numeric.norm());
        EXPECT_LT((analytic.col(j) - numeric).norm() / scale, 1e-4)
            << "state " << j << " at pixel " << u << ", " << v;
      }
      ++checked;
    }
  }
  EXPECT_GE(checked, 10);
}

INSTANTIATE_TEST_SUITE_P(StraightAndBending, TubularEkfJacobian, ::testing::Values(0.0, 2.5));

TEST(TubularEkf, FarFeaturesCountLessWithTheSquareOfTheirRange) {
  const Camera camera = ForwardCamera();
  TubularEkfOptions options;
  options.pixel_sigma = 0.5;
  options.far_feature_radii = 2.0;
  const double radius = 0.1;
  const TubularEkf filter(camera, Eigen::Isometry3d::Identity(), Eigen::Vector3d::UnitZ(), radius,
                          options);
  const double base = 2.0 * 0.5 * 0.5;  // both frames' localisation
  EXPECT_DOUBLE_EQ(filter.InnovationVariance(0.0, radius), base);
  // At 2 radii the variance doubles; at 4 radii it is 1 + 2^4 = 17 times.
  EXPECT_DOUBLE_EQ(filter.InnovationVariance(0.2, radius), 2.0 * base);
  EXPECT_NEAR(filter.InnovationVariance(0.4, radius), 17.0 * base, 1e-12);
  options.far_feature_radii = 0.0;
  const TubularEkf plain(camera, Eigen::Isometry3d::Identity(), Eigen::Vector3d::UnitZ(), radius,
                         options);
  EXPECT_DOUBLE_EQ(plain.InnovationVariance(0.4, radius), base);
}

// Wall points of a chain of straight cylinders (the true tube), a camera carried along it, and
// the matches an ideal tracker would give (exact projections plus noise).
struct SyntheticTube {
  std::vector<TubeSection> sections;  // the truth; section i ends where i + 1 starts
  std::vector<Eigen::Vector3d> points;
};

// Points scattered on each section's wall between its start and the next's.
SyntheticTube MakeTube(const std::vector<TubeSection>& sections, double length_of_last,
                       int points_per_metre, std::mt19937* random) {
  SyntheticTube tube{sections, {}};
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (std::size_t i = 0; i < sections.size(); ++i) {
    const TubeSection& s = sections[i];
    const double length =
        i + 1 < sections.size() ? s.AxialCoordinate(sections[i + 1].start) : length_of_last;
    const Eigen::Matrix<double, 3, 2> basis = OrthogonalBasis(s.axis);
    const int count = static_cast<int>(length * points_per_metre);
    for (int k = 0; k < count; ++k) {
      const double along = (i == 0 ? -0.2 : 0.0) + unit(*random) * length;
      const double phi = 2.0 * M_PI * unit(*random);
      tube.points.push_back(s.start + along * s.axis +
                            s.Radius() *
                                (std::cos(phi) * basis.col(0) + std::sin(phi) * basis.col(1)));
    }
  }
  return tube;
}

// Whether `point` lies inside the chain of sections, each cut from the next by the plane that
// bisects their axes at their junction (a mitred joint).
bool InsideTube(const SyntheticTube& tube, const Eigen::Vector3d& point) {
  const std::size_t count = tube.sections.size();
  for (std::size_t i = 0; i < count; ++i) {
    const TubeSection& s = tube.sections[i];
    if (i > 0) {
      const Eigen::Vector3d normal = (tube.sections[i - 1].axis + s.axis).normalized();
      if ((point - s.start).dot(normal) < 0.0) continue;
    }
    if (i + 1 < count) {
      const Eigen::Vector3d normal = (s.axis + tube.sections[i + 1].axis).normalized();
      if ((point - tube.sections[i + 1].start).dot(normal) > 0.0) continue;
    }
    return s.DistanceFromAxis(point) < s.Radius();
  }
  return false;
}

// Whether the wall point is seen from `camera_position`: the sight line stays inside the tube.
bool Visible(const SyntheticTube& tube, const Eigen::Vector3d& camera_position,
             const Eigen::Vector3d& point) {
  for (int k = 1; k < 100; ++k) {
    const double f = k / 100.0;
    if (!InsideTube(tube, camera_position + f * 0.999 * (point - camera_position))) return false;
  }
  return true;
}

std::vector<TubularEkfMatch> Matches(const Camera& camera, const SyntheticTube& tube,
                                     const Eigen::Isometry3d& previous,
                                     const Eigen::Isometry3d& current, double noise_px,
                                     std::mt19937* random) {
  std::normal_distribution<double> noise(0.0, noise_px);
  std::vector<TubularEkfMatch> matches;
  const Eigen::Isometry3d previous_from_world = previous.inverse();
  const Eigen::Isometry3d current_from_world = current.inverse();
  for (std::size_t i = 0; i < tube.points.size(); ++i) {
    Eigen::Vector2d a, b;
    if (camera.Project(previous_from_world * tube.points[i], &a) != ProjectionStatus::kValid ||
        camera.Project(current_from_world * tube.points[i], &b) != ProjectionStatus::kValid) {
      continue;
    }
    // Only the wall within 6 radii, as a lit tube shows it, and not behind a corner.
    if ((previous_from_world * tube.points[i]).z() > 0.6) continue;
    if (!Visible(tube, previous.translation(), tube.points[i]) ||
        !Visible(tube, current.translation(), tube.points[i])) {
      continue;
    }
    a += Eigen::Vector2d(noise(*random), noise(*random));
    b += Eigen::Vector2d(noise(*random), noise(*random));
    TubularEkfMatch match;
    camera.Unproject(a, &match.previous_bearing);
    match.pixel = b;
    match.track_id = static_cast<long>(i);
    matches.push_back(match);
  }
  return matches;
}

TEST(TubularEkf, RecoversTheAxisAndTheCameraPlaceInAStraightTube) {
  const Camera camera = ForwardCamera();
  std::mt19937 random(7);
  const double radius = 0.1;
  TubeSection truth;
  truth.start = Eigen::Vector3d::Zero();
  truth.axis = Eigen::Vector3d::UnitZ();
  truth.log_radius = std::log(radius);
  const SyntheticTube tube = MakeTube({truth}, 1.5, 400, &random);
  // The camera starts 20 mm off the axis and looks 4 degrees away from it; the filter assumes
  // neither.
  const Eigen::Quaterniond tilt(Eigen::AngleAxisd(4.0 * M_PI / 180.0, Eigen::Vector3d::UnitX()));
  const Eigen::Vector3d start(0.02, -0.01, 0.0);
  const double speed = 0.05, dt = 1.0 / 15.0;
  auto pose_at = [&](int k) { return Pose(start + Eigen::Vector3d(0, 0, speed * dt * k), tilt); };
  TubularEkfOptions options;
  TubularEkf filter(camera, pose_at(0), Eigen::Vector3d::UnitZ(), radius, options);
  const int frames = 150;
  for (int k = 1; k <= frames; ++k) {
    filter.Predict(dt);
    const TubularEkfUpdate update =
        filter.Update(Matches(camera, tube, pose_at(k - 1), pose_at(k), 0.3, &random));
    ASSERT_TRUE(update.updated) << "frame " << k;
  }
  ASSERT_EQ(filter.Sections().size(), 1u) << "a straight tube needs one section";
  // The filter's world is the first camera's frame (its pose was given as pose_at(0)), so the
  // estimates compare with the truth directly.
  const TubeSection& estimate = filter.Sections().front().geometry;
  const double axis_error_deg =
      std::acos(std::min(1.0, std::abs(estimate.axis.dot(truth.axis)))) * 180.0 / M_PI;
  // Measured: 0.52 degrees, the section bending by 0.023 / m (a bend radius of 435 radii) over
  // the 0.5 m driven; 0.3 bounded it while sections could not bend.
  EXPECT_LT(axis_error_deg, 0.6);
  EXPECT_LT(estimate.curvature.norm() * radius, 0.005) << "a straight tube does not bend";
  EXPECT_LT(estimate.DistanceFromAxis(Eigen::Vector3d::Zero()), 0.002);
  EXPECT_NEAR(estimate.Radius(), radius, 0.002);
  const Eigen::Vector3d travelled = filter.WorldFromCam().translation() - pose_at(0).translation();
  const double distance = speed * dt * frames;
  EXPECT_NEAR(travelled.norm(), distance, 0.005 * distance);
  EXPECT_LT((filter.WorldFromCam().translation() - pose_at(frames).translation()).norm(), 0.003);
}

TEST(TubularEkf, StartsASecondSectionWhereTheTubeTurns) {
  const Camera camera = ForwardCamera();
  std::mt19937 random(11);
  const double radius = 0.1;
  const double kink_deg = 25.0;
  TubeSection first;
  first.axis = Eigen::Vector3d::UnitZ();
  first.log_radius = std::log(radius);
  TubeSection second = first;
  second.start = Eigen::Vector3d(0, 0, 0.8);
  second.axis = Eigen::AngleAxisd(kink_deg * M_PI / 180.0, Eigen::Vector3d::UnitY()) *
                Eigen::Vector3d::UnitZ();
  const SyntheticTube tube = MakeTube({first, second}, 1.0, 400, &random);
  const double step = 0.05 / 15.0, dt = 1.0 / 15.0;
  // Along the first axis to the kink, then along the second, turning with it over 5 cm.
  auto pose_at = [&](int k) {
    const double s = step * k;
    const double blend = std::clamp((s - 0.775) / 0.05, 0.0, 1.0);
    const Eigen::Vector3d tangent = ((1 - blend) * first.axis + blend * second.axis).normalized();
    const Eigen::Vector3d position = s <= 0.8
                                         ? Eigen::Vector3d(0, 0, s)
                                         : Eigen::Vector3d(second.start + (s - 0.8) * second.axis);
    return Pose(position, LookAlong(tangent, Eigen::Vector3d::UnitY()));
  };
  TubularEkf filter(camera, pose_at(0), Eigen::Vector3d::UnitZ(), radius, {});
  const int frames = 420;  // 1.4 m
  int first_spawn = -1;
  for (int k = 1; k <= frames; ++k) {
    filter.Predict(dt);
    const TubularEkfUpdate update =
        filter.Update(Matches(camera, tube, pose_at(k - 1), pose_at(k), 0.3, &random));
    if (update.spawned_section && first_spawn < 0) first_spawn = k;
  }
  ASSERT_GE(filter.Sections().size(), 2u) << "the kink must start a section";
  // The kink comes into view 0.6 m ahead (6 radii) and the filter notices it from the tracks'
  // drift: the first new section starts before the camera reaches it.
  EXPECT_GT(first_spawn * step, 0.8 - 0.6);
  EXPECT_LT(first_spawn * step, 0.8);
  EXPECT_FALSE(filter.Sections()[1].reason.empty());
  // The last section's axis follows the second leg.
  const Eigen::Vector3d& last_axis = filter.Sections().back().geometry.axis;
  const double axis_error_deg = std::acos(std::min(1.0, last_axis.dot(second.axis))) * 180.0 / M_PI;
  const double end_error_m =
      (filter.WorldFromCam().translation() - pose_at(frames).translation()).norm();
  std::printf("second leg's axis %.2f deg off, the camera %.1f mm off after 1.4 m\n",
              axis_error_deg, 1000.0 * end_error_m);
  EXPECT_LT(axis_error_deg, 2.0);
  // Measured: the second leg's axis 0.42 degrees off and the camera 21 mm off after 1.4 m; with
  // straight sections only 1.9 degrees and 25 mm (with the new sections' radius freer,
  // new_section_radius_sigma 0.05, 0.1 degrees and 35 mm, the second section's radius 3 % short).
  // The straight tube above stays within 3 mm.
  EXPECT_LT(end_error_m, 0.035);
}

}  // namespace
}  // namespace pipescope
