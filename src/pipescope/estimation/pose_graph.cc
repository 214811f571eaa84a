#include "pipescope/estimation/pose_graph.h"

#include <ceres/ceres.h>

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "pipescope/util/error.h"

namespace pipescope {
namespace {

using Matrix6d = Eigen::Matrix<double, 6, 6>;

// The whitened 6-D error of one edge (001 §III-E's edge: a relative pose and its covariance).
// The translation error is taken in the `from` frame, where the odometry measured it, and the
// rotation error is 2 vec(dq), twice the vector part of the small quaternion between measured
// and estimated: to first order the rotation vector of dq, so that a rotation sigma in radians
// means what it says.
class RelativePoseError {
 public:
  RelativePoseError(const Eigen::Isometry3d& from_T_to, const Matrix6d& sqrt_information)
      : measured_translation_(from_T_to.translation()),
        measured_rotation_inverse_(Eigen::Quaterniond(from_T_to.linear()).normalized().conjugate()),
        sqrt_information_(sqrt_information) {}

  // Positions are 3 values, rotations Eigen's quaternion storage (x, y, z, w).
  template <typename T>
  bool operator()(const T* from_position, const T* from_rotation, const T* to_position,
                  const T* to_rotation, T* residual) const {
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> p_from(from_position);
    const Eigen::Map<const Eigen::Quaternion<T>> q_from(from_rotation);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> p_to(to_position);
    const Eigen::Map<const Eigen::Quaternion<T>> q_to(to_rotation);
    const Eigen::Quaternion<T> from_inverse = q_from.conjugate();
    const Eigen::Matrix<T, 3, 1> estimated_translation = from_inverse * (p_to - p_from);
    const Eigen::Quaternion<T> rotation_error =
        measured_rotation_inverse_.template cast<T>() * (from_inverse * q_to);
    Eigen::Matrix<T, 6, 1> error;
    error.template head<3>() = estimated_translation - measured_translation_.template cast<T>();
    error.template tail<3>() = T(2.0) * rotation_error.vec();
    Eigen::Map<Eigen::Matrix<T, 6, 1>> whitened(residual);
    whitened = sqrt_information_.template cast<T>() * error;
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Isometry3d& from_T_to,
                                     const Matrix6d& sqrt_information) {
    return new ceres::AutoDiffCostFunction<RelativePoseError, 6, 3, 4, 3, 4>(
        new RelativePoseError(from_T_to, sqrt_information));
  }

 private:
  Eigen::Vector3d measured_translation_;
  Eigen::Quaterniond measured_rotation_inverse_;
  Matrix6d sqrt_information_;
};

std::string EdgeName(int index, const PoseGraphEdge& edge) {
  return "pose graph edge " + std::to_string(index) + " (" + std::to_string(edge.from) + " -> " +
         std::to_string(edge.to) + ")";
}

// The upper factor U with U^T U = information, so that |U e|^2 = e^T I e; throws when the
// information cannot be an inverse covariance.
Matrix6d SquareRootInformation(int index, const PoseGraphEdge& edge) {
  const Matrix6d& information = edge.information;
  if (!information.allFinite() ||
      (information - information.transpose()).norm() > 1e-9 * information.norm()) {
    throw InputError(EdgeName(index, edge) + ": information matrix is not finite and symmetric");
  }
  const Eigen::LLT<Matrix6d> cholesky(information);
  if (cholesky.info() != Eigen::Success) {
    throw InputError(EdgeName(index, edge) + ": information matrix is not positive definite");
  }
  return cholesky.matrixU();
}

void CheckEdge(int index, const PoseGraphEdge& edge, int pose_count) {
  if (edge.from < 0 || edge.from >= pose_count || edge.to < 0 || edge.to >= pose_count) {
    throw InputError(EdgeName(index, edge) + ": pose index out of range [0, " +
                     std::to_string(pose_count) + ")");
  }
  if (edge.from == edge.to) throw InputError(EdgeName(index, edge) + ": joins a pose to itself");
  if (!edge.from_T_to.matrix().allFinite()) {
    throw InputError(EdgeName(index, edge) + ": relative pose is not finite");
  }
  if (!(edge.huber_scale >= 0.0) || !std::isfinite(edge.huber_scale)) {
    throw InputError(EdgeName(index, edge) + ": Huber scale must be 0 or positive");
  }
}

// One vertex's parameter blocks, as Ceres edits them.
struct VertexParameters {
  std::array<double, 3> position;
  std::array<double, 4> rotation;  // x, y, z, w
};

}  // namespace

Matrix6d IsotropicPoseInformation(double translation_sigma_m, double rotation_sigma_rad) {
  if (!(translation_sigma_m > 0.0) || !(rotation_sigma_rad > 0.0)) {
    throw std::invalid_argument("pose sigmas must be positive");
  }
  Eigen::Matrix<double, 6, 1> diagonal;
  diagonal.head<3>().setConstant(1.0 / (translation_sigma_m * translation_sigma_m));
  diagonal.tail<3>().setConstant(1.0 / (rotation_sigma_rad * rotation_sigma_rad));
  return diagonal.asDiagonal();
}

std::vector<PoseGraphEdge> ConsecutivePoseEdges(
    const std::vector<Eigen::Isometry3d>& world_from_cam, double translation_sigma_m,
    double rotation_sigma_rad) {
  const Matrix6d information = IsotropicPoseInformation(translation_sigma_m, rotation_sigma_rad);
  std::vector<PoseGraphEdge> edges;
  for (int i = 0; i + 1 < static_cast<int>(world_from_cam.size()); ++i) {
    edges.push_back({i, i + 1, world_from_cam[i].inverse() * world_from_cam[i + 1], information});
  }
  return edges;
}

PoseGraphResult OptimisePoseGraph(const std::vector<PoseGraphEdge>& edges,
                                  std::vector<Eigen::Isometry3d>* world_from_cam,
                                  const PoseGraphOptions& options) {
  if (world_from_cam == nullptr) throw std::invalid_argument("OptimisePoseGraph: no poses");
  const int pose_count = static_cast<int>(world_from_cam->size());
  std::vector<Matrix6d> sqrt_information;
  for (int i = 0; i < static_cast<int>(edges.size()); ++i) {
    CheckEdge(i, edges[i], pose_count);
    sqrt_information.push_back(SquareRootInformation(i, edges[i]));
  }
  PoseGraphResult result;
  if (edges.empty()) {
    result.converged = true;
    return result;
  }

  std::vector<VertexParameters> vertices(pose_count);
  for (int i = 0; i < pose_count; ++i) {
    const Eigen::Isometry3d& pose = (*world_from_cam)[i];
    if (!pose.matrix().allFinite()) {
      throw InputError("pose graph vertex " + std::to_string(i) + " is not finite");
    }
    Eigen::Map<Eigen::Vector3d>(vertices[i].position.data()) = pose.translation();
    Eigen::Map<Eigen::Quaterniond>(vertices[i].rotation.data()) =
        Eigen::Quaterniond(pose.linear()).normalized();
  }

  ceres::Problem problem;
  for (int i = 0; i < static_cast<int>(edges.size()); ++i) {
    VertexParameters& from = vertices[edges[i].from];
    VertexParameters& to = vertices[edges[i].to];
    ceres::LossFunction* loss =
        edges[i].huber_scale > 0.0 ? new ceres::HuberLoss(edges[i].huber_scale) : nullptr;
    problem.AddResidualBlock(RelativePoseError::Create(edges[i].from_T_to, sqrt_information[i]),
                             loss, from.position.data(), from.rotation.data(),
                             to.position.data(), to.rotation.data());
  }
  for (VertexParameters& vertex : vertices) {
    if (!problem.HasParameterBlock(vertex.rotation.data())) continue;  // on no edge
    problem.SetManifold(vertex.rotation.data(), new ceres::EigenQuaternionManifold);
  }
  if (problem.HasParameterBlock(vertices[0].position.data())) {
    problem.SetParameterBlockConstant(vertices[0].position.data());
    problem.SetParameterBlockConstant(vertices[0].rotation.data());
  }

  ceres::Solver::Options solver;
  solver.linear_solver_type =
      ceres::IsSparseLinearAlgebraLibraryTypeAvailable(solver.sparse_linear_algebra_library_type)
          ? ceres::SPARSE_NORMAL_CHOLESKY
          : ceres::DENSE_QR;
  solver.max_num_iterations = options.max_iterations;
  solver.function_tolerance = options.function_tolerance;
  solver.num_threads = options.num_threads;
  solver.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);

  result.converged = summary.termination_type == ceres::CONVERGENCE;
  result.initial_cost = summary.initial_cost;
  result.final_cost = summary.final_cost;
  result.iterations = summary.num_successful_steps + summary.num_unsuccessful_steps;
  // The first pose, and poses on no edge, keep their input bit for bit.
  for (int i = 1; i < pose_count; ++i) {
    if (!problem.HasParameterBlock(vertices[i].position.data())) continue;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = Eigen::Map<const Eigen::Quaterniond>(vertices[i].rotation.data())
                        .normalized()
                        .toRotationMatrix();
    pose.translation() = Eigen::Map<const Eigen::Vector3d>(vertices[i].position.data());
    (*world_from_cam)[i] = pose;
  }
  return result;
}

}  // namespace pipescope
