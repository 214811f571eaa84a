#include "pipescope/estimation/rigid_point_alignment.h"

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <string>

#include "pipescope/util/error.h"

namespace pipescope {
namespace {

// first ~ transform * second: a rigid motion, or a similarity with_scale.
Eigen::Affine3d Fit(const std::vector<Eigen::Vector3d>& first,
                    const std::vector<Eigen::Vector3d>& second, const std::vector<int>& pairs,
                    bool with_scale) {
  Eigen::Matrix3Xd from(3, pairs.size()), to(3, pairs.size());
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    from.col(i) = second[pairs[i]];
    to.col(i) = first[pairs[i]];
  }
  return Eigen::Affine3d(Eigen::umeyama(from, to, with_scale));
}

std::vector<int> Inliers(const std::vector<Eigen::Vector3d>& first,
                         const std::vector<Eigen::Vector3d>& second, const Eigen::Affine3d& t,
                         double threshold) {
  std::vector<int> inliers;
  for (int i = 0; i < static_cast<int>(first.size()); ++i) {
    if ((t * second[i] - first[i]).norm() < threshold) inliers.push_back(i);
  }
  return inliers;
}

}  // namespace

RigidAlignment AlignPointPairs(const std::vector<Eigen::Vector3d>& first,
                               const std::vector<Eigen::Vector3d>& second,
                               const RigidAlignmentOptions& options) {
  if (first.size() != second.size()) {
    throw InputError("AlignPointPairs: " + std::to_string(first.size()) + " and " +
                     std::to_string(second.size()) + " points");
  }
  RigidAlignment result;
  const int n = static_cast<int>(first.size());
  if (n < 3) return result;
  std::mt19937_64 random(options.seed);
  std::uniform_int_distribution<int> pick(0, n - 1);
  std::vector<int> best;
  for (int iteration = 0; iteration < options.iterations; ++iteration) {
    const std::vector<int> sample = {pick(random), pick(random), pick(random)};
    if (sample[0] == sample[1] || sample[1] == sample[2] || sample[0] == sample[2]) continue;
    // Three points nearly on a line leave the rotation about it free.
    const Eigen::Vector3d a = second[sample[1]] - second[sample[0]];
    const Eigen::Vector3d b = second[sample[2]] - second[sample[0]];
    if (a.cross(b).norm() < 1e-3 * a.norm() * b.norm()) continue;
    std::vector<int> inliers = Inliers(
        first, second, Fit(first, second, sample, options.with_scale), options.inlier_threshold_m);
    if (inliers.size() > best.size()) best = std::move(inliers);
  }
  if (best.size() < 3) return result;
  // Refit on the inliers, then once more on the refit's inliers.
  for (int round = 0; round < 2; ++round) {
    std::vector<int> inliers = Inliers(first, second, Fit(first, second, best, options.with_scale),
                                       options.inlier_threshold_m);
    if (inliers.size() < 3) break;
    best = std::move(inliers);
  }
  const Eigen::Affine3d fit = Fit(first, second, best, options.with_scale);
  result.scale = std::cbrt(fit.linear().determinant());
  result.first_from_second.linear() = fit.linear() / result.scale;
  result.first_from_second.translation() = fit.translation();
  double sum = 0.0;
  for (int i : best) sum += (fit * second[i] - first[i]).squaredNorm();
  result.rms_m = std::sqrt(sum / best.size());
  result.inliers = best;
  result.found = true;
  return result;
}

}  // namespace pipescope
