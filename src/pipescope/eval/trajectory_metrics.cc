#include "pipescope/eval/trajectory_metrics.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "pipescope/io/association.h"
#include "pipescope/util/error.h"

namespace pipescope {
namespace {

// The matched frames, in time order.
struct MatchedPoses {
  std::vector<Eigen::Vector3d> gt_positions;
  std::vector<Eigen::Vector3d> est_positions;
  std::vector<Eigen::Quaterniond> gt_rotations;
  std::vector<Eigen::Quaterniond> est_rotations;
};

void CheckOptions(const EvaluationOptions& options) {
  if (!(options.max_dt_s >= 0)) throw std::invalid_argument("EvaluationOptions: max_dt_s < 0");
  if (!(options.rpe_segment_m > 0)) {
    throw std::invalid_argument("EvaluationOptions: rpe_segment_m must be positive");
  }
  if (!(options.path_step_m >= 0)) {
    throw std::invalid_argument("EvaluationOptions: path_step_m < 0");
  }
  if (!(options.min_return_fraction > 0 && options.min_return_fraction <= 1)) {
    throw std::invalid_argument("EvaluationOptions: min_return_fraction outside (0, 1]");
  }
}

std::string TimeSpan(const Trajectory& trajectory) {
  std::ostringstream text;
  text << trajectory.size() << " poses";
  if (!trajectory.empty()) {
    text.precision(17);
    text << " in [" << trajectory.front().timestamp << ", " << trajectory.back().timestamp << "] s";
  }
  return text.str();
}

// Distances along the run (000 §6.1). Distances use the raw estimate: aligning with Sim(3)
// first would hide exactly the scale error eq. 50 measures.
void ComputeDistances(const MatchedPoses& poses, double min_return_fraction, Metrics* metrics) {
  const auto& gt = poses.gt_positions;
  const auto& est = poses.est_positions;
  const std::size_t last = gt.size() - 1;
  // The turnaround is the frame farthest from the start.
  std::size_t turnaround = 0;
  double max_reach = 0;
  for (std::size_t i = 0; i < gt.size(); ++i) {
    const double reach = (gt[i] - gt[0]).norm();
    if (reach > max_reach) {
      max_reach = reach;
      turnaround = i;
    }
  }
  const double gt_net = (gt[last] - gt[0]).norm();
  const double est_net = (est[last] - est[0]).norm();
  const double return_gt = (gt[last] - gt[turnaround]).norm();
  metrics->out_and_back = max_reach > 0 && return_gt >= min_return_fraction * max_reach;
  if (!metrics->out_and_back) {
    metrics->distance_gt_m = gt_net;
    metrics->distance_est_m = est_net;
    metrics->distance_error_pct = PercentError(gt_net, est_net);
    return;
  }
  const double forward_gt = (gt[turnaround] - gt[0]).norm();
  const double reverse_gt = (gt[last] - gt[turnaround]).norm();
  const double forward_est = (est[turnaround] - est[0]).norm();
  const double reverse_est = (est[last] - est[turnaround]).norm();
  metrics->distance_gt_m = forward_gt + reverse_gt;
  metrics->distance_est_m = forward_est + reverse_est;
  metrics->distance_error_pct = PercentError(metrics->distance_gt_m, metrics->distance_est_m);
  metrics->forward_error_pct = PercentError(forward_gt, forward_est);
  metrics->reverse_error_pct = PercentError(reverse_gt, reverse_est);
  // 000 eq. 51: |forward_est - reverse_est| / (2 gt), how much farther the run went out than it
  // came back, for a ground truth that returns exactly. Generalised to a ground truth whose legs
  // differ by comparing the legs' differences, over the whole path. Like eq. 51's distances down
  // the pipe, it does not count where across the pipe each run ends: a robot that drifts 4 mm
  // sideways over a 3.4 m leg changes that leg's length by 2 micrometres. (Comparing how far
  // each run ends from its start, as before session 10, counted that drift in full.)
  metrics->return_error_pct = 100.0 *
                              std::abs((forward_est - reverse_est) - (forward_gt - reverse_gt)) /
                              metrics->distance_gt_m;
}

// The length of the path travelled, on both trajectories over the same frames: those where the
// ground truth has advanced at least `step_m` since the last one taken, and the last frame.
void ComputePathLengths(const MatchedPoses& poses, double step_m, Metrics* metrics) {
  const auto& gt = poses.gt_positions;
  const auto& est = poses.est_positions;
  std::size_t last_taken = 0;
  double gt_since = 0.0;
  for (std::size_t i = 1; i < gt.size(); ++i) {
    gt_since += (gt[i] - gt[i - 1]).norm();
    if (gt_since < step_m && i + 1 < gt.size()) continue;
    metrics->path_gt_m += (gt[i] - gt[last_taken]).norm();
    metrics->path_est_m += (est[i] - est[last_taken]).norm();
    last_taken = i;
    gt_since = 0.0;
  }
  if (metrics->path_gt_m > 0) {
    metrics->path_error_pct = PercentError(metrics->path_gt_m, metrics->path_est_m);
  }
}

// Absolute trajectory error: position residuals after aligning the estimate to ground truth.
void ComputeAbsoluteError(const MatchedPoses& poses, Alignment alignment, Metrics* metrics) {
  const SimilarityTransform gt_from_est =
      AlignPositions(poses.est_positions, poses.gt_positions, alignment);
  double sum_squared = 0;
  double max_error = 0;
  for (std::size_t i = 0; i < poses.gt_positions.size(); ++i) {
    const double error = (gt_from_est(poses.est_positions[i]) - poses.gt_positions[i]).norm();
    sum_squared += error * error;
    max_error = std::max(max_error, error);
  }
  metrics->alignment = alignment;
  metrics->ate_rmse_m = std::sqrt(sum_squared / poses.gt_positions.size());
  metrics->ate_max_m = max_error;
  // Turned so that the first orientations agree: a position-only alignment leaves the rotation
  // about a straight path arbitrary, the first pose does not.
  const Eigen::Quaterniond align_rotation =
      poses.gt_rotations.front() * poses.est_rotations.front().conjugate();
  double sum_squared_deg = 0;
  double max_deg = 0;
  for (std::size_t i = 0; i < poses.gt_rotations.size(); ++i) {
    const double angle_deg =
        poses.gt_rotations[i].angularDistance(align_rotation * poses.est_rotations[i]) * 180.0 /
        M_PI;
    sum_squared_deg += angle_deg * angle_deg;
    max_deg = std::max(max_deg, angle_deg);
  }
  metrics->rot_rmse_deg = std::sqrt(sum_squared_deg / poses.gt_rotations.size());
  metrics->rot_max_deg = max_deg;
  if (alignment == Alignment::kSim3) metrics->scale = gt_from_est.scale;
}

// Relative pose error over segments of `segment_m` ground-truth path length: the translation
// between the segment's ends, expressed in the frame of its first camera, compared between
// estimate and ground truth. Unset when no segment is that long.
std::optional<double> RelativeTranslationErrorPct(const MatchedPoses& poses, double segment_m) {
  const auto& gt = poses.gt_positions;
  const auto& est = poses.est_positions;
  const std::size_t n = gt.size();
  std::vector<double> path_length(n, 0.0);
  for (std::size_t i = 1; i < n; ++i)
    path_length[i] = path_length[i - 1] + (gt[i] - gt[i - 1]).norm();
  // Tolerates the rounding of the cumulative sum, so steps that add up to the segment length
  // reach it.
  const double reach = segment_m * (1 - 1e-9);
  double sum_squared = 0;
  std::size_t count = 0;
  std::size_t b = 1;
  for (std::size_t a = 0; a + 1 < n; ++a) {
    b = std::max(b, a + 1);
    while (b < n && path_length[b] - path_length[a] < reach) ++b;
    if (b == n) break;  // Later frames a have even less path ahead of them.
    const Eigen::Vector3d est_step = poses.est_rotations[a].conjugate() * (est[b] - est[a]);
    const Eigen::Vector3d gt_step = poses.gt_rotations[a].conjugate() * (gt[b] - gt[a]);
    sum_squared += (est_step - gt_step).squaredNorm();
    ++count;
  }
  if (count == 0) return std::nullopt;
  return 100.0 * std::sqrt(sum_squared / count) / segment_m;
}

}  // namespace

std::optional<double> PercentError(double ground_truth, double estimate) {
  if (ground_truth == 0) return std::nullopt;
  return 100.0 * std::abs((ground_truth - estimate) / ground_truth);
}

Metrics EvaluateTrajectory(const Trajectory& ground_truth, const Trajectory& estimate,
                           const EvaluationOptions& options) {
  CheckOptions(options);
  const std::vector<AssociatedPair> pairs =
      AssociateByTimestamp(ground_truth, estimate, options.max_dt_s);
  if (pairs.size() < 2) {
    std::ostringstream message;
    message << "only " << pairs.size() << " estimated poses match a ground-truth pose within "
            << options.max_dt_s << " s; at least 2 are needed (the ground truth has "
            << TimeSpan(ground_truth) << ", the estimate has " << TimeSpan(estimate) << ")";
    throw InputError(message.str());
  }
  MatchedPoses poses;
  for (const AssociatedPair& pair : pairs) {
    poses.gt_positions.push_back(ground_truth[pair.gt_index].position);
    poses.gt_rotations.push_back(ground_truth[pair.gt_index].rotation);
    poses.est_positions.push_back(estimate[pair.est_index].position);
    poses.est_rotations.push_back(estimate[pair.est_index].rotation);
  }
  Metrics metrics;
  metrics.frames_gt = ground_truth.size();
  metrics.frames_est = estimate.size();
  metrics.frames_matched = pairs.size();
  ComputeDistances(poses, options.min_return_fraction, &metrics);
  ComputePathLengths(poses, options.path_step_m, &metrics);
  ComputeAbsoluteError(poses, options.alignment, &metrics);
  metrics.rpe_1m_pct = RelativeTranslationErrorPct(poses, options.rpe_segment_m);
  return metrics;
}

}  // namespace pipescope
