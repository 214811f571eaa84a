#include "pipescope/geometry/sphere_relative_pose.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <opencv2/core/utility.hpp>
#include <random>

namespace pipescope {
namespace {

constexpr double kPi = 3.14159265358979323846;

double AngleDeg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle() * 180.0 / kPi;
}

double ColatitudeDeg(const Eigen::Vector3d& bearing) {
  return std::acos(std::clamp(bearing.z(), -1.0, 1.0)) * 180.0 / kPi;
}

// Points on the wall of a 400 mm pipe around a forward-moving camera, seen from two poses;
// about a third of the bearings lie beyond 90 degrees from the optical axis.
struct SphereScene {
  std::vector<Eigen::Vector3d> bearings_i, bearings_j;
  Eigen::Matrix3d rotation;  // cam_j_from_cam_i
  Eigen::Vector3d translation;
  int beyond_90_deg = 0;
};

SphereScene MakeScene(double noise_rad, double outlier_fraction, std::uint64_t seed) {
  SphereScene scene;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::normal_distribution<double> noise(0.0, noise_rad);
  scene.rotation = (Eigen::AngleAxisd(0.04, Eigen::Vector3d::UnitX()) *
                    Eigen::AngleAxisd(-0.03, Eigen::Vector3d::UnitY()) *
                    Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitZ()))
                       .toRotationMatrix();
  // Camera j is 30 mm ahead and 5 mm aside of camera i (in camera i's frame).
  const Eigen::Vector3d centre_j_in_i(0.005, -0.002, 0.03);
  scene.translation = -scene.rotation * centre_j_in_i;
  const auto perturb = [&](const Eigen::Vector3d& bearing) {
    return (bearing + Eigen::Vector3d(noise(rng), noise(rng), noise(rng))).normalized();
  };
  for (int k = 0; k < 300; ++k) {
    const double phi = kPi * uniform(rng);
    const double z = 0.6 * uniform(rng) + 0.1;  // from 0.5 m behind to 0.7 m ahead
    const Eigen::Vector3d point_i(0.2 * std::cos(phi), 0.2 * std::sin(phi), z);
    const Eigen::Vector3d point_j = scene.rotation * point_i + scene.translation;
    Eigen::Vector3d eta_i = perturb(point_i.normalized());
    Eigen::Vector3d eta_j = perturb(point_j.normalized());
    if (k < outlier_fraction * 300) {
      eta_j = Eigen::Vector3d(uniform(rng), uniform(rng), uniform(rng)).normalized();
    } else if (ColatitudeDeg(eta_i) > 90.0 && ColatitudeDeg(eta_j) > 90.0) {
      ++scene.beyond_90_deg;
    }
    scene.bearings_i.push_back(eta_i);
    scene.bearings_j.push_back(eta_j);
  }
  return scene;
}

TEST(SphereRelativePoseTest, RecoversKnownPoseWithBearingsBeyond90Degrees) {
  const SphereScene scene = MakeScene(/*noise_rad=*/0.001, /*outlier_fraction=*/0.3, 7);
  ASSERT_GT(scene.beyond_90_deg, 40);
  const SphereRelativePose pose = EstimateSphereRelativePose(scene.bearings_i, scene.bearings_j);
  ASSERT_TRUE(pose.success);
  EXPECT_LT(AngleDeg(pose.rotation, scene.rotation), 0.1);
  const double direction_error_deg =
      std::acos(std::clamp(pose.translation.dot(scene.translation.normalized()), -1.0, 1.0)) *
      180.0 / kPi;
  EXPECT_LT(direction_error_deg, 2.0);
  // The outliers (the first 30 %) are rejected, the inliers kept.
  int true_inliers = 0, false_inliers = 0;
  for (int k = 0; k < 300; ++k) {
    if (!pose.inliers[k]) continue;
    (k < 90 ? false_inliers : true_inliers)++;
  }
  EXPECT_GT(true_inliers, 0.95 * 210);
  EXPECT_LT(false_inliers, 5);
}

TEST(SphereRelativePoseTest, ExactOnNoiseFreeBearingsBehindTheCamera) {
  // Only bearings more than 90 degrees from the optical axis (z < 0): no pinhole normalisation
  // exists for any of them.
  SphereScene scene = MakeScene(0.0, 0.0, 11);
  std::vector<Eigen::Vector3d> behind_i, behind_j;
  for (std::size_t k = 0; k < scene.bearings_i.size(); ++k) {
    if (scene.bearings_i[k].z() < 0 && scene.bearings_j[k].z() < 0) {
      behind_i.push_back(scene.bearings_i[k]);
      behind_j.push_back(scene.bearings_j[k]);
    }
  }
  ASSERT_GE(behind_i.size(), 20u);
  const SphereRelativePose pose = EstimateSphereRelativePose(behind_i, behind_j);
  ASSERT_TRUE(pose.success);
  EXPECT_EQ(pose.num_inliers, static_cast<int>(behind_i.size()));
  EXPECT_LT(AngleDeg(pose.rotation, scene.rotation), 1e-6);
  EXPECT_NEAR(pose.translation.dot(scene.translation.normalized()), 1.0, 1e-9);
}

TEST(SphereRelativePoseTest, LinearEssentialSatisfiesEpipolarConstraintAndDecomposes) {
  const SphereScene scene = MakeScene(0.0, 0.0, 3);
  std::vector<int> indices(scene.bearings_i.size());
  for (std::size_t k = 0; k < indices.size(); ++k) indices[k] = static_cast<int>(k);
  Eigen::Matrix3d essential;
  ASSERT_TRUE(EssentialFromBearingsLinear(scene.bearings_i, scene.bearings_j, indices, &essential));
  for (std::size_t k = 0; k < indices.size(); ++k) {
    EXPECT_LT(SphereEpipolarError(essential, scene.bearings_i[k], scene.bearings_j[k]), 1e-9);
  }
  Eigen::Matrix3d rotation;
  Eigen::Vector3d translation;
  const int positive = DecomposeEssentialOnSphere(essential, scene.bearings_i, scene.bearings_j, {},
                                                  &rotation, &translation);
  EXPECT_EQ(positive, static_cast<int>(indices.size()));
  EXPECT_LT(AngleDeg(rotation, scene.rotation), 1e-6);
  // The midpoint depths reproduce the point at the true scale.
  double depth_i, depth_j;
  ASSERT_TRUE(TriangulateDepthsMidpoint(scene.rotation, scene.translation, scene.bearings_i[0],
                                        scene.bearings_j[0], &depth_i, &depth_j));
  const Eigen::Vector3d point_i = depth_i * scene.bearings_i[0];
  EXPECT_NEAR(std::hypot(point_i.x(), point_i.y()), 0.2, 1e-9);
}

// An eight-point sample is solved by a QR of A^T, more points by the eigen-decomposition of
// A^T A: on noise-free bearings both give the true essential matrix (the eight with a ninth
// row repeated go the eigen way), and a sample of fewer than 8 independent rows is refused.
TEST(SphereRelativePoseTest, EightPointSampleGivesTheEssentialOfMorePoints) {
  const SphereScene scene = MakeScene(0.0, 0.0, 17);
  for (int start = 0; start + 8 <= 40; start += 8) {
    std::vector<int> sample(8);
    for (int k = 0; k < 8; ++k) sample[k] = start + k;
    Eigen::Matrix3d from_qr, from_eigen;
    ASSERT_TRUE(EssentialFromBearingsLinear(scene.bearings_i, scene.bearings_j, sample, &from_qr));
    std::vector<int> nine = sample;
    nine.push_back(sample[3]);
    ASSERT_TRUE(EssentialFromBearingsLinear(scene.bearings_i, scene.bearings_j, nine, &from_eigen));
    const double sign = (from_qr.cwiseProduct(from_eigen)).sum() < 0 ? -1.0 : 1.0;
    EXPECT_LT((from_qr - sign * from_eigen).norm(), 1e-8) << start;
    for (int k = 0; k < 40; ++k) {
      EXPECT_LT(SphereEpipolarError(from_qr, scene.bearings_i[k], scene.bearings_j[k]), 1e-9);
    }
    std::vector<int> repeated = sample;
    repeated[7] = repeated[2];  // 7 independent rows
    Eigen::Matrix3d refused;
    EXPECT_FALSE(
        EssentialFromBearingsLinear(scene.bearings_i, scene.bearings_j, repeated, &refused));
  }
}

TEST(SphereRelativePoseTest, MotionPriorFindsThePoseAmongMostlyWrongMatches) {
  // 75 % wrong matches: an all-inlier eight-point sample has probability 0.25^8 = 1.5e-5, so
  // 200 random samples almost never find the pose; a prior a few tenths of a degree and a few
  // degrees of direction off the truth seeds the inlier set, and the refinement recovers it.
  const SphereScene scene = MakeScene(/*noise_rad=*/0.0005, /*outlier_fraction=*/0.75, 13);
  SphereRelativePoseOptions options;
  options.max_iterations = 200;
  options.inlier_threshold_rad = 0.01;
  const Eigen::Matrix3d prior_rotation =
      Eigen::AngleAxisd(0.003, Eigen::Vector3d::UnitY()).toRotationMatrix() * scene.rotation;
  const Eigen::Vector3d prior_translation =
      (scene.translation.normalized() + Eigen::Vector3d(0.03, -0.02, 0.0)).normalized();
  Eigen::Matrix3d skew;
  skew << 0, -prior_translation.z(), prior_translation.y(), prior_translation.z(), 0,
      -prior_translation.x(), -prior_translation.y(), prior_translation.x(), 0;
  const SphereRelativePose without =
      EstimateSphereRelativePose(scene.bearings_i, scene.bearings_j, options);
  const SphereRelativePose with = EstimateSphereRelativePose(scene.bearings_i, scene.bearings_j,
                                                             options, {skew * prior_rotation});
  ASSERT_TRUE(with.success);
  EXPECT_LT(AngleDeg(with.rotation, scene.rotation), 0.1);
  EXPECT_GT(with.translation.dot(scene.translation.normalized()), std::cos(2.0 * kPi / 180.0));
  EXPECT_GT(with.num_inliers, 0.9 * 75);
  EXPECT_GT(with.num_inliers, without.num_inliers);
}

// The RANSAC loop scores its hypotheses on all cores; it must still stop where, and keep the
// hypothesis that, the plain sequential loop does. The oracle is that loop written out with the
// same generator and eight-point solver. 30 % of the matches are wrong and the motion prior is
// 0.2 degrees off, so random samples beat it and the loop stops inside a batch.
TEST(SphereRelativePoseTest, ParallelRansacTakesTheSequentialLoopsHypothesis) {
  const SphereScene scene = MakeScene(/*noise_rad=*/0.001, /*outlier_fraction=*/0.3, 11);
  SphereRelativePoseOptions options;
  options.refine = false;  // the RANSAC winner's inliers are then returned as they are
  const Eigen::Matrix3d prior_rotation =
      Eigen::AngleAxisd(0.0035, Eigen::Vector3d::UnitY()).toRotationMatrix() * scene.rotation;
  const Eigen::Vector3d prior_translation = scene.translation.normalized();
  Eigen::Matrix3d skew;
  skew << 0, -prior_translation.z(), prior_translation.y(), prior_translation.z(), 0,
      -prior_translation.x(), -prior_translation.y(), prior_translation.x(), 0;
  const Eigen::Matrix3d prior = skew * prior_rotation;

  const int n = static_cast<int>(scene.bearings_i.size());
  const auto count_inliers = [&](const Eigen::Matrix3d& essential, std::vector<char>* inliers) {
    inliers->assign(n, 0);
    int count = 0;
    for (int m = 0; m < n; ++m) {
      (*inliers)[m] = SphereEpipolarError(essential, scene.bearings_i[m], scene.bearings_j[m]) <
                      options.inlier_threshold_rad;
      count += (*inliers)[m];
    }
    return count;
  };
  const auto samples_needed = [&](int inliers) {
    return static_cast<int>(
        std::ceil(std::log(1.0 - options.confidence) /
                  std::log(1.0 - std::pow(static_cast<double>(inliers) / n, 8))));
  };
  std::vector<char> best_inliers;
  int best = count_inliers(prior, &best_inliers);
  // Above 10 % inliers the sample count fits an int.
  ASSERT_GT(best, n / 10);
  int needed = samples_needed(best), iteration = 0, improvements = 0;
  std::mt19937_64 rng(options.seed);
  std::vector<int> all(n);
  std::iota(all.begin(), all.end(), 0);
  std::vector<int> sample(8);
  std::vector<char> inliers;
  for (; iteration < std::max(needed, options.min_iterations) && iteration < options.max_iterations;
       ++iteration) {
    for (int k = 0; k < 8; ++k) {
      std::uniform_int_distribution<int> pick(k, n - 1);
      std::swap(all[k], all[pick(rng)]);
      sample[k] = all[k];
    }
    Eigen::Matrix3d essential;
    if (!EssentialFromBearingsLinear(scene.bearings_i, scene.bearings_j, sample, &essential)) {
      continue;
    }
    const int count = count_inliers(essential, &inliers);
    if (count <= best) continue;
    best = count;
    best_inliers = inliers;
    needed = samples_needed(best);
    ++improvements;
  }
  ASSERT_GE(improvements, 1);
  ASSERT_LT(iteration, options.max_iterations);  // stopped by the confidence
  ASSERT_NE(iteration % 64, 0);                  // not at the end of a batch of 64
  for (int threads : {1, 2}) {
    cv::setNumThreads(threads);
    const SphereRelativePose pose =
        EstimateSphereRelativePose(scene.bearings_i, scene.bearings_j, options, {prior});
    EXPECT_EQ(pose.iterations, iteration) << threads << " threads";
    EXPECT_EQ(pose.num_inliers, best) << threads << " threads";
    EXPECT_EQ(pose.inliers, best_inliers) << threads << " threads";
  }
  cv::setNumThreads(-1);
}

// The inlier test that skips the second image's error decides as SphereEpipolarError < threshold
// does: random essential matrices and unit bearings, most of them near the threshold (either
// image's error just above or below it), and bearings at the epipoles, where a normal vanishes.
TEST(SphereRelativePoseTest, InlierTestDecidesAsTheEpipolarError) {
  std::mt19937 rng(5);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const auto random_unit = [&] {
    return Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
  };
  const double threshold = 0.004;
  int inliers = 0, outliers = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const Eigen::Matrix3d rotation =
        Eigen::AngleAxisd(0.3 * uniform(rng), random_unit()).toRotationMatrix();
    const Eigen::Vector3d translation = random_unit();
    Eigen::Matrix3d skew;
    skew << 0, -translation.z(), translation.y(), translation.z(), 0, -translation.x(),
        -translation.y(), translation.x(), 0;
    const Eigen::Matrix3d essential = skew * rotation;
    const Eigen::Vector3d bearing_i =
        trial % 50 == 0 ? Eigen::Vector3d(rotation.transpose() * translation) : random_unit();
    Eigen::Vector3d bearing_j;
    if (trial % 50 == 1) {
      bearing_j = translation;  // at the epipole: E^T eta_j = 0
    } else {
      // On the epipolar plane of eta_i, then turned out of it by about the threshold.
      const Eigen::Vector3d plane_normal = (essential * bearing_i).normalized();
      const Eigen::Vector3d in_plane =
          (random_unit() - random_unit().dot(plane_normal) * plane_normal).normalized();
      const double angle = threshold * (0.6 + 0.6 * uniform(rng));
      bearing_j = (std::cos(angle) * in_plane + std::sin(angle) * plane_normal).normalized();
    }
    const bool expected = SphereEpipolarError(essential, bearing_i, bearing_j) < threshold;
    EXPECT_EQ(IsSphereEpipolarInlier(essential, bearing_i, bearing_j, threshold), expected)
        << "trial " << trial;
    (expected ? inliers : outliers) += 1;
  }
  EXPECT_GT(inliers, 500);  // both decisions are exercised
  EXPECT_GT(outliers, 500);
}

TEST(SphereRelativePoseTest, TooFewCorrespondencesFail) {
  const SphereScene scene = MakeScene(0.0, 0.0, 5);
  const std::vector<Eigen::Vector3d> few_i(scene.bearings_i.begin(), scene.bearings_i.begin() + 7);
  const std::vector<Eigen::Vector3d> few_j(scene.bearings_j.begin(), scene.bearings_j.begin() + 7);
  EXPECT_FALSE(EstimateSphereRelativePose(few_i, few_j).success);
}

}  // namespace
}  // namespace pipescope
