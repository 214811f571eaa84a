#include "pipescope/eval/alignment.h"

#include <gtest/gtest.h>

#include <random>
#include <string>

#include "pipescope/util/error.h"

namespace pipescope {
namespace {

const Eigen::Matrix3d kRotation =
    Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.3, -1.0, 0.5).normalized()).toRotationMatrix();
const Eigen::Vector3d kTranslation(1.5, -2.0, 0.25);

std::vector<Eigen::Vector3d> RandomPoints(int count) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> uniform(-3, 3);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < count; ++i) points.emplace_back(uniform(rng), uniform(rng), uniform(rng));
  return points;
}

// A straight pipe run: points along the Z axis, the degenerate case for rotation.
std::vector<Eigen::Vector3d> LinePoints(int count) {
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < count; ++i) points.emplace_back(0, 0, 0.1 * i);
  return points;
}

std::vector<Eigen::Vector3d> Transform(const std::vector<Eigen::Vector3d>& points, double scale) {
  std::vector<Eigen::Vector3d> out;
  for (const auto& p : points) out.push_back(scale * (kRotation * p) + kTranslation);
  return out;
}

double MaxResidual(const SimilarityTransform& transform, const std::vector<Eigen::Vector3d>& source,
                   const std::vector<Eigen::Vector3d>& target) {
  double max_residual = 0;
  for (std::size_t i = 0; i < source.size(); ++i) {
    max_residual = std::max(max_residual, (transform(source[i]) - target[i]).norm());
  }
  return max_residual;
}

TEST(Alignment, NamesRoundTripAndUnknownNameBlamesTheFlag) {
  for (Alignment alignment : {Alignment::kSe3, Alignment::kSim3, Alignment::kNone}) {
    EXPECT_EQ(AlignmentFromName(AlignmentName(alignment)), alignment);
  }
  try {
    AlignmentFromName("SE3x");
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("--align"), std::string::npos);
    EXPECT_NE(std::string(error.what()).find("SE3x"), std::string::npos);
  }
}

TEST(Alignment, Se3RecoversKnownRigidTransform) {
  const auto source = RandomPoints(20);
  const auto target = Transform(source, 1.0);
  const SimilarityTransform transform = AlignPositions(source, target, Alignment::kSe3);
  EXPECT_LT((transform.rotation - kRotation).norm(), 1e-12);
  EXPECT_LT((transform.translation - kTranslation).norm(), 1e-12);
  EXPECT_EQ(transform.scale, 1.0);
}

TEST(Alignment, Sim3RecoversKnownScale) {
  const auto source = RandomPoints(20);
  const auto target = Transform(source, 2.5);
  const SimilarityTransform transform = AlignPositions(source, target, Alignment::kSim3);
  EXPECT_NEAR(transform.scale, 2.5, 1e-12);
  EXPECT_LT((transform.rotation - kRotation).norm(), 1e-12);
  EXPECT_LT(MaxResidual(transform, source, target), 1e-12);
  // Se3 on the same points cannot absorb the scale.
  EXPECT_GT(MaxResidual(AlignPositions(source, target, Alignment::kSe3), source, target), 0.5);
}

TEST(Alignment, CollinearPointsStillAlign) {
  // Rotation about the line is undetermined, but every point must land on its target.
  for (int count : {2, 3, 50}) {
    const auto source = LinePoints(count);
    const auto target = Transform(source, 1.0);
    const SimilarityTransform se3 = AlignPositions(source, target, Alignment::kSe3);
    EXPECT_LT(MaxResidual(se3, source, target), 1e-12) << count;
    EXPECT_NEAR(se3.rotation.determinant(), 1.0, 1e-12);
    EXPECT_LT((se3.rotation.transpose() * se3.rotation - Eigen::Matrix3d::Identity()).norm(),
              1e-12);

    const auto scaled_target = Transform(source, 0.8);
    const SimilarityTransform sim3 = AlignPositions(source, scaled_target, Alignment::kSim3);
    EXPECT_NEAR(sim3.scale, 0.8, 1e-12) << count;
    EXPECT_LT(MaxResidual(sim3, source, scaled_target), 1e-12) << count;
  }
}

TEST(Alignment, SinglePointGivesTranslation) {
  const std::vector<Eigen::Vector3d> source = {{1, 2, 3}};
  const std::vector<Eigen::Vector3d> target = {{4, 4, 4}};
  for (Alignment alignment : {Alignment::kSe3, Alignment::kSim3}) {
    const SimilarityTransform transform = AlignPositions(source, target, alignment);
    EXPECT_EQ(transform.rotation, Eigen::Matrix3d::Identity());
    EXPECT_EQ(transform.scale, 1.0);
    EXPECT_EQ(transform.translation, Eigen::Vector3d(3, 2, 1));
  }
}

TEST(Alignment, NoneIsIdentity) {
  const auto source = RandomPoints(5);
  const SimilarityTransform transform =
      AlignPositions(source, Transform(source, 2.0), Alignment::kNone);
  EXPECT_EQ(transform.rotation, Eigen::Matrix3d::Identity());
  EXPECT_EQ(transform.translation, Eigen::Vector3d::Zero());
  EXPECT_EQ(transform.scale, 1.0);
}

}  // namespace
}  // namespace pipescope
