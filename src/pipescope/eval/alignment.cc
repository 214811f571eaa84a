#include "pipescope/eval/alignment.h"

#include <Eigen/Geometry>
#include <stdexcept>

#include "pipescope/util/error.h"

namespace pipescope {
namespace {

// Below this mean squared spread (m^2) the source has no shape to rotate or scale.
constexpr double kMinSourceVariance = 1e-18;

Eigen::Matrix3Xd ToMatrix(const std::vector<Eigen::Vector3d>& points) {
  Eigen::Matrix3Xd matrix(3, points.size());
  for (std::size_t i = 0; i < points.size(); ++i) matrix.col(i) = points[i];
  return matrix;
}

}  // namespace

Alignment AlignmentFromName(const std::string& name) {
  if (name == "se3") return Alignment::kSe3;
  if (name == "sim3") return Alignment::kSim3;
  if (name == "none") return Alignment::kNone;
  throw InputError("--align: unknown alignment '" + name + "' (expected se3, sim3 or none)");
}

std::string AlignmentName(Alignment alignment) {
  switch (alignment) {
    case Alignment::kSe3:
      return "se3";
    case Alignment::kSim3:
      return "sim3";
    case Alignment::kNone:
      return "none";
  }
  return "unknown";
}

SimilarityTransform AlignPositions(const std::vector<Eigen::Vector3d>& source,
                                   const std::vector<Eigen::Vector3d>& target,
                                   Alignment alignment) {
  if (source.size() != target.size()) {
    throw std::invalid_argument("AlignPositions: source and target differ in length");
  }
  SimilarityTransform transform;
  if (alignment == Alignment::kNone || source.empty()) return transform;

  const Eigen::Matrix3Xd src = ToMatrix(source);
  const Eigen::Matrix3Xd dst = ToMatrix(target);
  const Eigen::Vector3d src_mean = src.rowwise().mean();
  const double src_variance = (src.colwise() - src_mean).squaredNorm() / src.cols();
  if (src_variance < kMinSourceVariance) {
    // One point, or all points equal: only the translation is determined (and umeyama's scale
    // would divide by zero).
    transform.translation = dst.rowwise().mean() - src_mean;
    return transform;
  }
  // Umeyama (1991). Collinear or coplanar points give a rank-deficient covariance; the
  // singular vectors of the zero singular values are arbitrary, and the reflection fix flips
  // only the last of them, so the rotation is exact on the span of the points.
  const Eigen::Matrix4d matrix = Eigen::umeyama(src, dst, alignment == Alignment::kSim3);
  const Eigen::Matrix3d scaled_rotation = matrix.topLeftCorner<3, 3>();
  transform.scale = alignment == Alignment::kSim3 ? scaled_rotation.col(0).norm() : 1.0;
  // A scale of 0 (all target points equal) leaves no rotation to recover.
  if (transform.scale > 0) transform.rotation = scaled_rotation / transform.scale;
  transform.translation = matrix.topRightCorner<3, 1>();
  return transform;
}

}  // namespace pipescope
