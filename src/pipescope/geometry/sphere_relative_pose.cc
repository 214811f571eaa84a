#include "pipescope/geometry/sphere_relative_pose.h"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <opencv2/core/utility.hpp>
#include <random>

namespace pipescope {
namespace {

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

// Angle of eta_j from the epipolar plane of eta_i: eta_j^T (t x R eta_i) / |t x R eta_i|.
struct SphereEpipolarResidual {
  SphereEpipolarResidual(const Eigen::Vector3d& bearing_i, const Eigen::Vector3d& bearing_j)
      : bearing_i_(bearing_i), bearing_j_(bearing_j) {}

  template <typename T>
  bool operator()(const T* quaternion_wxyz, const T* translation, T* residual) const {
    const T eta_i[3] = {T(bearing_i_.x()), T(bearing_i_.y()), T(bearing_i_.z())};
    T rotated[3];
    ceres::QuaternionRotatePoint(quaternion_wxyz, eta_i, rotated);
    T normal[3];
    ceres::CrossProduct(translation, rotated, normal);
    const T norm = ceres::sqrt(normal[0] * normal[0] + normal[1] * normal[1] +
                               normal[2] * normal[2] + T(1e-18));
    residual[0] = (T(bearing_j_.x()) * normal[0] + T(bearing_j_.y()) * normal[1] +
                   T(bearing_j_.z()) * normal[2]) /
                  norm;
    return true;
  }

  Eigen::Vector3d bearing_i_;
  Eigen::Vector3d bearing_j_;
};

// The inliers of `essential` and their count. With `must_beat` >= 0 the count stops once it
// can no longer exceed must_beat (the hypothesis cannot win): then *count <= must_beat and the
// inliers are partial.
void CountInliers(const Eigen::Matrix3d& essential, const std::vector<Eigen::Vector3d>& bearings_i,
                  const std::vector<Eigen::Vector3d>& bearings_j, double threshold,
                  std::vector<char>* inliers, int* count, int must_beat = -1) {
  const int n = static_cast<int>(bearings_i.size());
  inliers->assign(n, 0);
  *count = 0;
  for (int k = 0; k < n; ++k) {
    if (*count + (n - k) <= must_beat) return;
    if (IsSphereEpipolarInlier(essential, bearings_i[k], bearings_j[k], threshold)) {
      (*inliers)[k] = 1;
      ++*count;
    }
  }
}

}  // namespace

bool EssentialFromBearingsLinear(const std::vector<Eigen::Vector3d>& bearings_i,
                                 const std::vector<Eigen::Vector3d>& bearings_j,
                                 const std::vector<int>& indices, Eigen::Matrix3d* essential) {
  if (indices.size() < 8) return false;
  // eta_j^T E eta_i = sum_rc eta_j[r] eta_i[c] E(r, c): one row of A e = 0 per correspondence.
  const auto row_of = [&](int index) {
    Eigen::Matrix<double, 9, 1> row;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) row(3 * r + c) = bearings_j[index](r) * bearings_i[index](c);
    }
    return row;
  };
  Eigen::Matrix<double, 9, 1> e;
  if (indices.size() == 8) {
    // A RANSAC sample: e spans the null space of the 8 x 9 A, the last column of Q in
    // A^T = Q R (Householder QR, a fifth of the work of the 9 x 9 eigen-decomposition below).
    Eigen::Matrix<double, 9, 8> transposed;
    for (int k = 0; k < 8; ++k) transposed.col(k) = row_of(indices[k]);
    const Eigen::HouseholderQR<Eigen::Matrix<double, 9, 8>> qr(transposed);
    const Eigen::Matrix<double, 8, 1> diagonal = qr.matrixQR().diagonal().head<8>().cwiseAbs();
    // Fewer than 8 independent rows: a vanishing pivot (the eigenvalue test's 1e-14 on
    // squared singular values, as 1e-7 on R's diagonal).
    if (diagonal.minCoeff() < 1e-7 * diagonal.maxCoeff()) return false;
    e = qr.householderQ() * Eigen::Matrix<double, 9, 1>::Unit(8);
  } else {
    Eigen::Matrix<double, 9, 9> normal = Eigen::Matrix<double, 9, 9>::Zero();
    for (int index : indices) {
      const Eigen::Matrix<double, 9, 1> row = row_of(index);
      normal.noalias() += row * row.transpose();
    }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 9, 9>> eigen(normal);
    if (eigen.info() != Eigen::Success) return false;
    // A rank-deficient system (fewer than 8 independent rows) has a second null vector.
    if (eigen.eigenvalues()(1) < 1e-14 * eigen.eigenvalues()(8)) return false;
    e = eigen.eigenvectors().col(0);
  }
  Eigen::Matrix3d raw;
  raw << e(0), e(1), e(2), e(3), e(4), e(5), e(6), e(7), e(8);
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(raw, Eigen::ComputeFullU | Eigen::ComputeFullV);
  *essential = svd.matrixU() * Eigen::Vector3d(1, 1, 0).asDiagonal() * svd.matrixV().transpose();
  return true;
}

double SphereEpipolarError(const Eigen::Matrix3d& essential, const Eigen::Vector3d& bearing_i,
                           const Eigen::Vector3d& bearing_j) {
  const Eigen::Vector3d normal_j = essential * bearing_i;
  const Eigen::Vector3d normal_i = essential.transpose() * bearing_j;
  const double algebraic = std::abs(bearing_j.dot(normal_j));
  const double norm_j = normal_j.norm();
  const double norm_i = normal_i.norm();
  if (norm_j < 1e-12 || norm_i < 1e-12) return algebraic;
  return std::max(algebraic / norm_j, algebraic / norm_i);
}

bool IsSphereEpipolarInlier(const Eigen::Matrix3d& essential, const Eigen::Vector3d& bearing_i,
                            const Eigen::Vector3d& bearing_j, double threshold) {
  const Eigen::Vector3d normal_j = essential * bearing_i;
  const double algebraic = std::abs(bearing_j.dot(normal_j));
  const double norm_j = normal_j.norm();
  // algebraic = |eta_i . E^T eta_j| <= |E^T eta_j| for a unit eta_i, so above 2e-12 the second
  // norm is not below SphereEpipolarError's 1e-12 floor either, and the error is at least
  // algebraic / norm_j: at or above the threshold that alone decides.
  if (norm_j >= 1e-12 && algebraic >= 2e-12 && !(algebraic / norm_j < threshold)) return false;
  return SphereEpipolarError(essential, bearing_i, bearing_j) < threshold;
}

bool TriangulateDepthsMidpoint(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation,
                               const Eigen::Vector3d& bearing_i, const Eigen::Vector3d& bearing_j,
                               double* depth_i, double* depth_j) {
  // Minimise |d_j eta_j - (d_i R eta_i + t)|^2 over (d_i, d_j).
  const Eigen::Vector3d a = rotation * bearing_i;
  const Eigen::Vector3d& b = bearing_j;
  const double ab = a.dot(b);
  const double det = 1.0 - ab * ab;  // |a| = |b| = 1
  if (det < 1e-12) return false;
  const double at = a.dot(translation);
  const double bt = b.dot(translation);
  // [1, -ab; -ab, 1] [d_i; d_j] = [-at; bt]
  *depth_i = (-at + ab * bt) / det;
  *depth_j = (bt - ab * at) / det;
  return true;
}

int DecomposeEssentialOnSphere(const Eigen::Matrix3d& essential,
                               const std::vector<Eigen::Vector3d>& bearings_i,
                               const std::vector<Eigen::Vector3d>& bearings_j,
                               const std::vector<char>& inliers, Eigen::Matrix3d* rotation,
                               Eigen::Vector3d* translation) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(essential, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d u = svd.matrixU();
  Eigen::Matrix3d v = svd.matrixV();
  if (u.determinant() < 0) u = -u;
  if (v.determinant() < 0) v = -v;
  Eigen::Matrix3d w;
  w << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  const Eigen::Matrix3d rotations[2] = {u * w * v.transpose(), u * w.transpose() * v.transpose()};
  const Eigen::Vector3d t = u.col(2);
  int best_count = -1;
  for (const Eigen::Matrix3d& r : rotations) {
    for (double sign : {1.0, -1.0}) {
      int count = 0;
      for (std::size_t k = 0; k < bearings_i.size(); ++k) {
        if (!inliers.empty() && !inliers[k]) continue;
        double depth_i, depth_j;
        if (TriangulateDepthsMidpoint(r, sign * t, bearings_i[k], bearings_j[k], &depth_i,
                                      &depth_j) &&
            depth_i > 0 && depth_j > 0) {
          ++count;
        }
      }
      if (count > best_count) {
        best_count = count;
        *rotation = r;
        *translation = sign * t;
      }
    }
  }
  return best_count;
}

namespace {

// Samples needed to draw one all-inlier eight-point sample with `confidence`.
int RansacIterationsNeeded(int inliers, int n, double confidence) {
  const double all_inlier_probability = std::pow(static_cast<double>(inliers) / n, 8);
  if (all_inlier_probability >= 1.0) return 0;
  return static_cast<int>(
      std::ceil(std::log(1.0 - confidence) / std::log(1.0 - all_inlier_probability + 1e-300)));
}
}  // namespace

SphereRelativePose EstimateSphereRelativePose(const std::vector<Eigen::Vector3d>& bearings_i,
                                              const std::vector<Eigen::Vector3d>& bearings_j,
                                              const SphereRelativePoseOptions& options,
                                              const std::vector<Eigen::Matrix3d>& priors) {
  SphereRelativePose result;
  const int n = static_cast<int>(bearings_i.size());
  if (n < 8 || bearings_j.size() != bearings_i.size()) return result;
  // Motion priors are scored like any hypothesis, before the random samples: with a third of
  // the matches right, an all-inlier eight-point sample is rare (0.3^8), a prior is not.
  for (const Eigen::Matrix3d& prior : priors) {
    std::vector<char> prior_inliers;
    int count = 0;
    CountInliers(prior, bearings_i, bearings_j, options.inlier_threshold_rad, &prior_inliers,
                 &count);
    if (count > result.num_inliers) {
      result.num_inliers = count;
      result.essential = prior;
      result.inliers = prior_inliers;
    }
  }
  std::mt19937_64 rng(options.seed);
  std::vector<int> all(n);
  std::iota(all.begin(), all.end(), 0);
  int needed = result.num_inliers > 0
                   ? RansacIterationsNeeded(result.num_inliers, n, options.confidence)
                   : options.max_iterations;
  const auto iterations_wanted = [&] {
    return std::min(std::max(needed, options.min_iterations), options.max_iterations);
  };
  // Hypotheses are drawn in order from the one generator and scored in batches on all cores,
  // then taken in draw order as the sequential loop would take them (stopping where it would
  // stop): the same pose whatever the thread count.
  struct Hypothesis {
    bool valid = false;
    Eigen::Matrix3d essential;
    std::vector<char> inliers;
    int count = 0;
  };
  constexpr int kBatch = 64;
  std::vector<std::array<int, 8>> samples(kBatch);
  std::vector<Hypothesis> hypotheses(kBatch);
  int iteration = 0;
  while (iteration < iterations_wanted()) {
    const int batch = std::min(kBatch, iterations_wanted() - iteration);
    for (int b = 0; b < batch; ++b) {
      // Eight distinct indices (partial Fisher-Yates).
      for (int k = 0; k < 8; ++k) {
        std::uniform_int_distribution<int> pick(k, n - 1);
        std::swap(all[k], all[pick(rng)]);
        samples[b][k] = all[k];
      }
    }
    const int best_before_batch = result.num_inliers;
    cv::parallel_for_(cv::Range(0, batch), [&](const cv::Range& range) {
      for (int b = range.start; b < range.end; ++b) {
        Hypothesis& hypothesis = hypotheses[b];
        hypothesis.valid = EssentialFromBearingsLinear(
            bearings_i, bearings_j, std::vector<int>(samples[b].begin(), samples[b].end()),
            &hypothesis.essential);
        if (!hypothesis.valid) continue;
        // A hypothesis with no more inliers than the best before the batch is never taken.
        CountInliers(hypothesis.essential, bearings_i, bearings_j, options.inlier_threshold_rad,
                     &hypothesis.inliers, &hypothesis.count, best_before_batch);
      }
    });
    for (int b = 0; b < batch && iteration < iterations_wanted(); ++b, ++iteration) {
      const Hypothesis& hypothesis = hypotheses[b];
      if (!hypothesis.valid || hypothesis.count <= result.num_inliers) continue;
      result.num_inliers = hypothesis.count;
      result.essential = hypothesis.essential;
      result.inliers = hypothesis.inliers;
      needed = RansacIterationsNeeded(hypothesis.count, n, options.confidence);
    }
  }
  result.iterations = iteration;
  if (result.num_inliers < 8) return result;

  // Re-estimate linearly on all inliers, then pick the cheiral (R, t).
  std::vector<int> inlier_indices;
  for (int k = 0; k < n; ++k) {
    if (result.inliers[k]) inlier_indices.push_back(k);
  }
  EssentialFromBearingsLinear(bearings_i, bearings_j, inlier_indices, &result.essential);
  DecomposeEssentialOnSphere(result.essential, bearings_i, bearings_j, result.inliers,
                             &result.rotation, &result.translation);

  if (options.refine) {
    Eigen::Quaterniond q(result.rotation);
    double quaternion_wxyz[4] = {q.w(), q.x(), q.y(), q.z()};
    double translation[3] = {result.translation.x(), result.translation.y(),
                             result.translation.z()};
    ceres::Problem problem;
    for (int k : inlier_indices) {
      problem.AddResidualBlock(new ceres::AutoDiffCostFunction<SphereEpipolarResidual, 1, 4, 3>(
                                   new SphereEpipolarResidual(bearings_i[k], bearings_j[k])),
                               new ceres::HuberLoss(options.inlier_threshold_rad), quaternion_wxyz,
                               translation);
    }
    problem.SetManifold(quaternion_wxyz, new ceres::QuaternionManifold);
    problem.SetManifold(translation, new ceres::SphereManifold<3>);
    ceres::Solver::Options solver_options;
    solver_options.max_num_iterations = options.refine_iterations;
    solver_options.linear_solver_type = ceres::DENSE_QR;
    solver_options.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    ceres::Solve(solver_options, &problem, &summary);
    if (summary.IsSolutionUsable()) {
      result.rotation = Eigen::Quaterniond(quaternion_wxyz[0], quaternion_wxyz[1],
                                           quaternion_wxyz[2], quaternion_wxyz[3])
                            .normalized()
                            .toRotationMatrix();
      result.translation =
          Eigen::Vector3d(translation[0], translation[1], translation[2]).normalized();
      result.essential = Skew(result.translation) * result.rotation;
      CountInliers(result.essential, bearings_i, bearings_j, options.inlier_threshold_rad,
                   &result.inliers, &result.num_inliers);
    }
  }
  result.success = result.num_inliers >= 8;
  return result;
}

}  // namespace pipescope
