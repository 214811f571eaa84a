#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

namespace pipescope {

// Relative pose from unit-sphere bearings (001 §III-A), for lenses past 180 degrees, where
// pinhole-normalised points (cv::findEssentialMat) do not exist.
//
// Which solver: OpenGV is not packaged for this machine's Debian, and Nister's minimal
// five-point solver [3] is not implemented here. The hypotheses come from the linear eight-point
// essential matrix on bearings (rows kron(eta_j, eta_i), projected onto the essential manifold),
// inside RANSAC; the best hypothesis is then refined on all inliers with Ceres, minimising the
// angle of each eta_j from the epipolar plane of eta_i (a geometric error on the sphere), with
// the rotation on SO(3) and the translation direction on S^2. The model and error are the same
// as a five-point RANSAC; only the hypothesis sample is larger (8 instead of 5), which costs
// RANSAC iterations, not accuracy.
struct SphereRelativePoseOptions {
  // Inlier threshold on the sine of the angle between a bearing and its epipolar plane, in
  // both images. 0.004 rad is about 1.2 px for the 190-degree 1280x960 lens (k1 ~ 300 px/rad).
  double inlier_threshold_rad = 0.004;
  int max_iterations = 4000;
  int min_iterations = 50;
  double confidence = 0.999;
  // Ceres refinement of the best hypothesis on its inliers (Huber at the threshold).
  bool refine = true;
  int refine_iterations = 20;
  std::uint64_t seed = 1;
};

// cam_j_from_cam_i: X_j = rotation * X_i + translation, with |translation| = 1.
// essential = [translation]_x rotation, so that eta_j^T E eta_i = 0 for a correspondence.
struct SphereRelativePose {
  bool success = false;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::UnitZ();
  Eigen::Matrix3d essential = Eigen::Matrix3d::Zero();
  std::vector<char> inliers;  // one per correspondence
  int num_inliers = 0;
  int iterations = 0;
};

// Linear eight-point essential matrix from >= 8 bearing pairs, projected onto the essential
// manifold (singular values 1, 1, 0). Returns false when the system is degenerate.
bool EssentialFromBearingsLinear(const std::vector<Eigen::Vector3d>& bearings_i,
                                 const std::vector<Eigen::Vector3d>& bearings_j,
                                 const std::vector<int>& indices, Eigen::Matrix3d* essential);

// max over both images of |eta^T n| / |n| for the epipolar plane normals n = E eta_i and
// E^T eta_j: the sine of the angle between each bearing and its epipolar plane. This is the
// quantity the guided ZNCC search bounds (001 §III-A uses |eta_j^T E eta_i|).
double SphereEpipolarError(const Eigen::Matrix3d& essential, const Eigen::Vector3d& bearing_i,
                           const Eigen::Vector3d& bearing_j);

// SphereEpipolarError(essential, bearing_i, bearing_j) < threshold for unit bearings, the same
// decision, without the second image's error where the first already reaches the threshold.
bool IsSphereEpipolarInlier(const Eigen::Matrix3d& essential, const Eigen::Vector3d& bearing_i,
                            const Eigen::Vector3d& bearing_j, double threshold);

// The depths along eta_i and eta_j of the midpoint triangulation of one correspondence under
// X_j = R X_i + t; false for near-parallel rays.
bool TriangulateDepthsMidpoint(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation,
                               const Eigen::Vector3d& bearing_i, const Eigen::Vector3d& bearing_j,
                               double* depth_i, double* depth_j);

// Of the four (R, t) of an essential matrix, the one with the most correspondences triangulated
// at positive depth along both bearings (cheirality on the sphere). Returns that count.
int DecomposeEssentialOnSphere(const Eigen::Matrix3d& essential,
                               const std::vector<Eigen::Vector3d>& bearings_i,
                               const std::vector<Eigen::Vector3d>& bearings_j,
                               const std::vector<char>& inliers, Eigen::Matrix3d* rotation,
                               Eigen::Vector3d* translation);

// RANSAC + refinement as described above. Needs at least 8 correspondences. `priors`:
// essential matrices of likely motions (e.g. the previous key-frame step), scored as RANSAC
// hypotheses before the random samples.
SphereRelativePose EstimateSphereRelativePose(const std::vector<Eigen::Vector3d>& bearings_i,
                                              const std::vector<Eigen::Vector3d>& bearings_j,
                                              const SphereRelativePoseOptions& options = {},
                                              const std::vector<Eigen::Matrix3d>& priors = {});

}  // namespace pipescope
