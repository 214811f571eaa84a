#include "pipescope/estimation/tubular_ekf.h"

#include <ceres/jet.h>
#include <ceres/rotation.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "pipescope/util/error.h"

namespace pipescope {
namespace {

// The most a new section inherits of a bending section's turn ahead of the camera
// (MaybeStartSection).
constexpr double kMaxInheritedTurnRad = 2.0 * M_PI / 180.0;

// Local perturbations the observation depends on: the current position (3) and rotation (3), the
// previous position (3) and rotation (3), and one section (7).
constexpr int kLocalSize = 19;
using Jet = ceres::Jet<double, kLocalSize>;

Eigen::Quaterniond ExpRotation(const Eigen::Vector3d& rotation_vector) {
  const double angle = rotation_vector.norm();
  if (angle < 1e-12) return Eigen::Quaterniond::Identity();
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, rotation_vector / angle));
}

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

// R (x) Exp(delta) applied to `vector`, with delta a Jet perturbation: R (Exp(delta) vector).
template <typename T>
Eigen::Matrix<T, 3, 1> RotatePerturbed(const Eigen::Quaterniond& rotation, const T* delta,
                                       const Eigen::Matrix<T, 3, 1>& vector) {
  Eigen::Matrix<T, 3, 1> rotated;
  ceres::AngleAxisRotatePoint(delta, vector.data(), rotated.data());
  return rotation.toRotationMatrix().cast<T>() * rotated;
}

}  // namespace

Eigen::Matrix<double, 3, 2> OrthogonalBasis(const Eigen::Vector3d& axis) {
  const Eigen::Vector3d helper =
      std::abs(axis.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  Eigen::Matrix<double, 3, 2> basis;
  basis.col(0) = axis.cross(helper).normalized();
  basis.col(1) = axis.cross(basis.col(0)).normalized();
  return basis;
}

TubularEkf::TubularEkf(const Camera& camera, const Eigen::Isometry3d& world_from_cam,
                       const Eigen::Vector3d& axis_in_camera, double radius,
                       const TubularEkfOptions& options)
    : camera_(camera), options_(options) {
  if (!(radius > 0.0)) throw InputError("TubularEkf: the radius must be positive");
  position_ = world_from_cam.translation();
  rotation_ = Eigen::Quaterniond(world_from_cam.rotation()).normalized();
  previous_position_ = position_;
  previous_rotation_ = rotation_;
  TubularEkfSection first;
  first.geometry.start = position_;
  first.geometry.axis = (rotation_ * axis_in_camera.normalized()).normalized();
  first.geometry.log_radius = prior_log_radius_ = std::log(radius);
  first.reason = "start";
  first.basis = OrthogonalBasis(first.geometry.axis);
  sections_.push_back(first);

  covariance_ = Eigen::MatrixXd::Zero(kCameraSize + kSectionSize, kCameraSize + kSectionSize);
  // The first pose fixes the world frame (gauge); the tiny variance keeps S positive definite.
  const double gauge = 1e-12;
  for (int i = 0; i < 6; ++i) covariance_(i, i) = covariance_(12 + i, 12 + i) = gauge;
  for (int i = 0; i < 3; ++i) {
    covariance_(kVelocity + i, kVelocity + i) =
        options.initial_speed_sigma * options.initial_speed_sigma;
    covariance_(kAngularVelocity + i, kAngularVelocity + i) =
        options.initial_angular_speed_sigma * options.initial_angular_speed_sigma;
  }
  const int s = kCameraSize;
  const double offset_sigma = options.initial_offset_sigma_radii * radius;
  for (int i = 0; i < 2; ++i) {
    covariance_(s + i, s + i) = offset_sigma * offset_sigma;
    covariance_(s + 2 + i, s + 2 + i) =
        options.initial_axis_sigma_rad * options.initial_axis_sigma_rad;
  }
  // Without a known radius the scale is a gauge too: hold log rho.
  const double radius_sigma = options.radius_prior_sigma > 0.0 ? options.radius_prior_sigma : 1e-9;
  covariance_(s + 4, s + 4) = radius_sigma * radius_sigma;
  const double curvature_sigma = options.curvature_sigma_radii / radius;
  for (int i = 5; i < 7; ++i) covariance_(s + i, s + i) = curvature_sigma * curvature_sigma;
}

Eigen::Isometry3d TubularEkf::WorldFromCam() const {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = rotation_.toRotationMatrix();
  pose.translation() = position_;
  return pose;
}

int TubularEkf::StateOffsetOfSection(int section) const {
  if (section < first_active_) return -1;
  return kCameraSize + kSectionSize * (section - first_active_);
}

void TubularEkf::Predict(double dt) {
  // Clone: the previous frame's pose is the current one, with the same uncertainty.
  previous_position_ = position_;
  previous_rotation_ = rotation_;
  const int n = StateSize();
  covariance_.block(kPreviousPosition, 0, 6, n) = covariance_.block(kPosition, 0, 6, n);
  covariance_.block(0, kPreviousPosition, n, 6) = covariance_.block(0, kPosition, n, 6);
  covariance_.block<6, 6>(kPreviousPosition, kPreviousPosition) =
      covariance_.block<6, 6>(kPosition, kPosition);

  // 004 eq. 6, noise-free part.
  const Eigen::Vector3d rotation_step = angular_velocity_ * dt;
  position_ += velocity_ * dt;
  rotation_ = (rotation_ * ExpRotation(rotation_step)).normalized();

  // Error-state transition: dr' = dr + dt dv; dtheta' = Exp(-w dt) dtheta + dt J_r(w dt) dw,
  // with J_r ~ I - [w dt]x / 2 to first order.
  Eigen::MatrixXd transition = Eigen::MatrixXd::Identity(n, n);
  transition.block<3, 3>(kPosition, kVelocity) = dt * Eigen::Matrix3d::Identity();
  transition.block<3, 3>(kRotation, kRotation) = ExpRotation(-rotation_step).toRotationMatrix();
  const Eigen::Matrix3d right_jacobian = Eigen::Matrix3d::Identity() - 0.5 * Skew(rotation_step);
  transition.block<3, 3>(kRotation, kAngularVelocity) = dt * right_jacobian;
  // Only the camera rows change; the clone and the sections are static (eq. 5: f_y = y).
  const Eigen::MatrixXd camera_rows = transition.topRows(12) * covariance_;
  covariance_.topRows(12) = camera_rows;
  const Eigen::MatrixXd camera_columns =
      covariance_.leftCols(12) * transition.topRows(12).leftCols(12).transpose();
  covariance_.leftCols(12) = camera_columns;

  // Velocity impulses V = a dt, Omega = theta dt (eq. 6) enter as dr += V dt, dv += V, and
  // dtheta += J_r dt Omega, dw += Omega.
  const double linear = options_.linear_acceleration_sigma * dt;
  const double angular = options_.angular_acceleration_sigma * dt;
  Eigen::Matrix<double, 12, 6> noise_map = Eigen::Matrix<double, 12, 6>::Zero();
  noise_map.block<3, 3>(kPosition, 0) = dt * Eigen::Matrix3d::Identity();
  noise_map.block<3, 3>(kVelocity, 0) = Eigen::Matrix3d::Identity();
  noise_map.block<3, 3>(kRotation, 3) = dt * right_jacobian;
  noise_map.block<3, 3>(kAngularVelocity, 3) = Eigen::Matrix3d::Identity();
  Eigen::Matrix<double, 6, 6> impulse = Eigen::Matrix<double, 6, 6>::Zero();
  impulse.diagonal() << linear * linear, linear * linear, linear * linear, angular * angular,
      angular * angular, angular * angular;
  covariance_.topLeftCorner<12, 12>() += noise_map * impulse * noise_map.transpose();
}

int TubularEkf::SectionOfRay(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                             double* range_out) const {
  // The chain: section i covers its axis from its junction with i - 1 to its junction with
  // i + 1; the first and last are open-ended. Start at the camera's section.
  const int count = static_cast<int>(sections_.size());
  // junction(i): between sections i - 1 and i. Computed where looked at, from the newest end:
  // the chain grows with the tube, and this runs for every feature of every update.
  auto junction = [&](int i) {
    return SectionJunction(sections_[i - 1].geometry, sections_[i].geometry);
  };
  int first = 0;
  for (int i = count - 1; i > 0; --i) {
    const TubeSection& section = sections_[i].geometry;
    if (section.ArcCoordinate(origin) >= section.ArcCoordinate(junction(i))) {
      first = i - 1;
      break;
    }
  }
  for (int i = first; i < count; ++i) {
    const TubeSection& section = sections_[i].geometry;
    double alpha = 0.0;
    if (!IntersectRayWithTubeSection<double>(origin, direction, section.start, section.axis,
                                             section.curvature, section.Radius(), &alpha)) {
      continue;
    }
    const Eigen::Vector3d point = origin + alpha * direction;
    const double along = section.ArcCoordinate(point);
    if (i > 0 && along < section.ArcCoordinate(junction(i))) continue;
    if (i + 1 < count && along > section.ArcCoordinate(junction(i + 1))) continue;
    const double range = std::abs(along - section.ArcCoordinate(origin));
    if (range > options_.max_range_radii * section.Radius()) return -1;
    if (range_out != nullptr) *range_out = range;
    return i;
  }
  return -1;
}

double TubularEkf::InnovationVariance(double range, double radius) const {
  const double base = 2.0 * options_.pixel_sigma * options_.pixel_sigma;
  if (options_.far_feature_radii <= 0.0) return base;
  const double relative = range / (options_.far_feature_radii * radius);
  return base * (1.0 + relative * relative * relative * relative);
}

bool TubularEkf::PredictPixel(const Eigen::Vector3d& previous_bearing, Eigen::Vector2d* pixel,
                              Eigen::MatrixXd* jacobian, double* variance) const {
  const Eigen::Vector3d origin = previous_position_;
  const Eigen::Vector3d direction = previous_rotation_ * previous_bearing;
  double range = 0.0;
  const int section_index = SectionOfRay(origin, direction, &range);
  if (section_index < 0) return false;
  const TubeSection& section = sections_[section_index].geometry;
  if (variance != nullptr) *variance = InnovationVariance(range, section.Radius());
  const Eigen::Matrix<double, 3, 2>& basis = sections_[section_index].basis;

  Jet e[kLocalSize];
  for (int i = 0; i < kLocalSize; ++i) e[i] = Jet(0.0, i);
  using Vec3 = Eigen::Matrix<Jet, 3, 1>;
  const Vec3 position = position_.cast<Jet>() + Vec3(e[0], e[1], e[2]);
  const Vec3 previous_position = previous_position_.cast<Jet>() + Vec3(e[6], e[7], e[8]);
  const Vec3 ray = RotatePerturbed<Jet>(previous_rotation_, e + 9, previous_bearing.cast<Jet>());
  const Vec3 start =
      section.start.cast<Jet>() + basis.cast<Jet>() * Eigen::Matrix<Jet, 2, 1>(e[12], e[13]);
  Vec3 axis = section.axis.cast<Jet>() + basis.cast<Jet>() * Eigen::Matrix<Jet, 2, 1>(e[14], e[15]);
  axis /= sqrt(axis.squaredNorm());
  const Jet radius = exp(Jet(section.log_radius) + e[16]);
  const Vec3 curvature =
      section.curvature.cast<Jet>() + basis.cast<Jet>() * Eigen::Matrix<Jet, 2, 1>(e[17], e[18]);
  Jet alpha;
  // 004 eq. 8: the wall point of the previous frame's ray (on a torus segment where the section
  // bends).
  if (!IntersectRayWithTubeSection<Jet>(previous_position, ray, start, axis, curvature, radius,
                                        &alpha)) {
    return false;
  }
  const Vec3 wall_point = previous_position + alpha * ray;
  // Into the current camera: (R Exp(dtheta))^T (X - r) = Exp(-dtheta) R^T (X - r).
  const Vec3 in_world = wall_point - position;
  const Vec3 unrotated = rotation_.conjugate().toRotationMatrix().cast<Jet>() * in_world;
  const Jet minus_delta[3] = {-e[3], -e[4], -e[5]};
  Vec3 point_cam;
  ceres::AngleAxisRotatePoint(minus_delta, unrotated.data(), point_cam.data());

  const Eigen::Vector3d point_value(point_cam[0].a, point_cam[1].a, point_cam[2].a);
  Eigen::Matrix<double, 2, 3> d_pixel_d_point;
  const ProjectionStatus status =
      camera_.ProjectWithJacobians(point_value, pixel, &d_pixel_d_point, nullptr);
  if (status == ProjectionStatus::kBehindCamera ||
      status == ProjectionStatus::kOutsideFieldOfView) {
    return false;
  }
  if (jacobian == nullptr) return true;
  Eigen::Matrix<double, 3, kLocalSize> d_point;
  for (int r = 0; r < 3; ++r) d_point.row(r) = point_cam[r].v.transpose();
  const Eigen::Matrix<double, 2, kLocalSize> local = d_pixel_d_point * d_point;
  jacobian->setZero(2, StateSize());
  jacobian->block<2, 3>(0, kPosition) = local.block<2, 3>(0, 0);
  jacobian->block<2, 3>(0, kRotation) = local.block<2, 3>(0, 3);
  jacobian->block<2, 3>(0, kPreviousPosition) = local.block<2, 3>(0, 6);
  jacobian->block<2, 3>(0, kPreviousRotation) = local.block<2, 3>(0, 9);
  const int offset = StateOffsetOfSection(section_index);
  // A frozen section is fixed geometry: it constrains the camera only.
  if (offset >= 0)
    jacobian->block<2, kSectionSize>(0, offset) = local.block<2, kSectionSize>(0, 12);
  return true;
}

void TubularEkf::Inject(const Eigen::VectorXd& delta) {
  position_ += delta.segment<3>(kPosition);
  rotation_ = (rotation_ * ExpRotation(delta.segment<3>(kRotation))).normalized();
  velocity_ += delta.segment<3>(kVelocity);
  angular_velocity_ += delta.segment<3>(kAngularVelocity);
  previous_position_ += delta.segment<3>(kPreviousPosition);
  previous_rotation_ =
      (previous_rotation_ * ExpRotation(delta.segment<3>(kPreviousRotation))).normalized();
  for (int i = first_active_; i < static_cast<int>(sections_.size()); ++i) {
    TubeSection& section = sections_[i].geometry;
    Eigen::Matrix<double, 3, 2>& basis = sections_[i].basis;
    const int offset = StateOffsetOfSection(i);
    section.start += basis * delta.segment<2>(offset);
    section.axis = (section.axis + basis * delta.segment<2>(offset + 2)).normalized();
    section.log_radius += delta[offset + 4];
    section.curvature += basis * delta.segment<2>(offset + 5);
    section.curvature -= section.curvature.dot(section.axis) * section.axis;
    // Turn the basis with the axis (the smallest rotation): project and re-orthonormalise.
    basis.col(0) = (basis.col(0) - basis.col(0).dot(section.axis) * section.axis).normalized();
    basis.col(1) = section.axis.cross(basis.col(0));
  }
}

TubularEkf::Nominal TubularEkf::SaveNominal() const {
  return {position_, velocity_,          angular_velocity_, previous_position_,
          rotation_, previous_rotation_, sections_};
}

void TubularEkf::RestoreNominal(const Nominal& nominal) {
  position_ = nominal.position;
  velocity_ = nominal.velocity;
  angular_velocity_ = nominal.angular_velocity;
  previous_position_ = nominal.previous_position;
  rotation_ = nominal.rotation;
  previous_rotation_ = nominal.previous_rotation;
  sections_ = nominal.sections;
}

TubularEkfUpdate TubularEkf::Update(const std::vector<TubularEkfMatch>& matches) {
  ++updates_;
  TubularEkfUpdate update;
  update.matches = static_cast<int>(matches.size());
  const int n = StateSize();

  // Gate each feature against the prediction (first linearisation), which also fixes its
  // innovation variance for this update.
  std::vector<int> used;
  std::vector<double> variance(matches.size(), 0.0);
  Eigen::Vector2d pixel;
  Eigen::MatrixXd jacobian;
  for (int i = 0; i < update.matches; ++i) {
    if (!PredictPixel(matches[i].previous_bearing, &pixel, &jacobian, &variance[i])) {
      ++update.unplaced;
      continue;
    }
    const Eigen::Vector2d innovation = matches[i].pixel - pixel;
    const Eigen::Matrix2d s =
        jacobian * covariance_ * jacobian.transpose() + variance[i] * Eigen::Matrix2d::Identity();
    const double nis = innovation.dot(s.ldlt().solve(innovation));
    if (nis > options_.gate_chi2) {
      ++update.gated;
      continue;
    }
    used.push_back(i);
  }
  if (static_cast<int>(used.size()) > options_.max_features) {
    std::vector<int> thinned;
    for (int k = 0; k < options_.max_features; ++k) {
      thinned.push_back(used[static_cast<std::size_t>(k) * used.size() / options_.max_features]);
    }
    used = std::move(thinned);
  }
  update.used = static_cast<int>(used.size());
  if (update.used < options_.min_features) {
    update.spawned_section = MaybeStartSection(update);
    return update;
  }

  // Iterated update: e_{i+1} = K_i (z - h(x_i) + H_i e_i), x_{i+1} = x_0 [+] e_{i+1}.
  const Nominal prior = SaveNominal();
  const int m = 2 * update.used;
  Eigen::MatrixXd h(m, n);
  Eigen::VectorXd residual(m);
  Eigen::VectorXd noise(m);  // the diagonal of R
  for (int k = 0; k < update.used; ++k) noise.segment<2>(2 * k).setConstant(variance[used[k]]);
  Eigen::VectorXd correction = Eigen::VectorXd::Zero(n);
  Eigen::MatrixXd gain;
  std::vector<char> placed(update.used, 1);
  for (int iteration = 0; iteration < std::max(1, options_.iterations); ++iteration) {
    for (int k = 0; k < update.used; ++k) {
      const TubularEkfMatch& match = matches[used[k]];
      if (!PredictPixel(match.previous_bearing, &pixel, &jacobian)) {
        placed[k] = 0;
        h.middleRows(2 * k, 2).setZero();
        residual.segment<2>(2 * k).setZero();
        continue;
      }
      placed[k] = 1;
      h.middleRows(2 * k, 2) = jacobian;
      residual.segment<2>(2 * k) = match.pixel - pixel;
    }
    const Eigen::MatrixXd ph = covariance_ * h.transpose();
    Eigen::MatrixXd s = h * ph;
    s.diagonal() += noise;
    gain = s.ldlt().solve(ph.transpose()).transpose();
    correction = gain * (residual + h * correction);
    RestoreNominal(prior);
    Inject(correction);
  }
  // Joseph form: P = (I - K H) P (I - K H)^T + K R K^T.
  const Eigen::MatrixXd i_kh = Eigen::MatrixXd::Identity(n, n) - gain * h;
  covariance_ =
      i_kh * covariance_ * i_kh.transpose() + gain * noise.asDiagonal() * gain.transpose();
  covariance_ = 0.5 * (covariance_ + covariance_.transpose()).eval();

  // Statistics of the posterior residuals.
  double nis_sum = 0.0, squared_sum = 0.0;
  int counted = 0;
  for (int k = 0; k < update.used; ++k) {
    if (!PredictPixel(matches[used[k]].previous_bearing, &pixel, nullptr)) continue;
    const Eigen::Vector2d innovation = matches[used[k]].pixel - pixel;
    squared_sum += innovation.squaredNorm();
    nis_sum += innovation.squaredNorm() / variance[used[k]];
    ++counted;
  }
  update.mean_nis = counted > 0 ? nis_sum / counted : 0.0;
  update.rms_innovation_px = counted > 0 ? std::sqrt(squared_sum / (2.0 * counted)) : 0.0;
  update.updated = true;
  MeasureTrackDrift(matches, &update);
  update.spawned_section = MaybeStartSection(update);
  return update;
}

void TubularEkf::MeasureTrackDrift(const std::vector<TubularEkfMatch>& matches,
                                   TubularEkfUpdate* update) {
  const Eigen::Isometry3d cam_from_world = WorldFromCam().inverse();
  std::unordered_map<long, TrackAnchor> seen;
  std::vector<double> drifts;
  track_drifts_.clear();
  for (const TubularEkfMatch& match : matches) {
    if (match.track_id < 0) continue;
    const auto anchor = anchors_.find(match.track_id);
    if (anchor != anchors_.end()) {
      seen.emplace(match.track_id, anchor->second);
      const int age = updates_ - anchor->second.first_update;
      if (age < options_.track_min_age_frames || age > options_.track_max_age_frames) continue;
      Eigen::Vector2d pixel;
      if (camera_.Project(cam_from_world * anchor->second.wall_point, &pixel) ==
          ProjectionStatus::kBehindCamera) {
        continue;
      }
      drifts.push_back((pixel - match.pixel).norm());
      track_drifts_.emplace_back(sections_.back().geometry.ArcCoordinate(anchor->second.wall_point),
                                 drifts.back());
      continue;
    }
    // A new track: its wall point from the previous frame's (now updated) pose.
    const Eigen::Vector3d direction = previous_rotation_ * match.previous_bearing;
    const int section = SectionOfRay(previous_position_, direction);
    if (section < 0) continue;
    const TubeSection& geometry = sections_[section].geometry;
    double alpha = 0.0;
    if (!IntersectRayWithTubeSection<double>(previous_position_, direction, geometry.start,
                                             geometry.axis, geometry.curvature, geometry.Radius(),
                                             &alpha)) {
      continue;
    }
    // Only the newest section's wall points test it: the chain behind it is settled.
    if (section != static_cast<int>(sections_.size()) - 1) continue;
    seen.emplace(match.track_id, TrackAnchor{previous_position_ + alpha * direction, updates_ - 1});
  }
  anchors_ = std::move(seen);
  update->drift_tracks = static_cast<int>(drifts.size());
  if (drifts.empty()) return;
  std::nth_element(drifts.begin(), drifts.begin() + drifts.size() / 2, drifts.end());
  update->track_drift_px = drifts[drifts.size() / 2];
}

bool TubularEkf::MaybeStartSection(const TubularEkfUpdate& update) {
  const int considered = update.used + update.gated;
  const double gated_fraction =
      considered > 0 ? static_cast<double>(update.gated) / considered : 0.0;
  const bool drifting = update.track_drift_px > options_.spawn_track_drift_px;
  unexplained_run_ =
      gated_fraction > options_.spawn_gated_fraction || drifting ? unexplained_run_ + 1 : 0;
  const TubeSection& current = sections_.back().geometry;
  const double here = current.ArcCoordinate(position_);
  const double travel = velocity_.dot(current.TangentAt(here)) >= 0.0 ? 1.0 : -1.0;
  if (unexplained_run_ < options_.spawn_frames) return false;
  // The new section starts ahead of the camera, where the features that misfit lie; the
  // current one must keep a useful length.
  double ahead = options_.spawn_lookahead_radii * current.Radius();
  if (drifting) {
    std::vector<double> where;
    for (const auto& [along, drift] : track_drifts_) {
      if (drift > options_.spawn_track_drift_px) where.push_back(along);
    }
    if (!where.empty()) {
      // The tenth of the drifting wall points nearest the camera along the travel.
      std::sort(where.begin(), where.end(),
                [&](double a, double b) { return travel * a < travel * b; });
      ahead = std::max(ahead, travel * (where[where.size() / 10] - here));
    }
  }
  // The new section leaves the current one along its tangent at the junction. After a bending
  // section the tube has changed between the camera and the misfitting features (the misfit
  // grows with the square of the distance past the change), so a junction placed there would
  // pass on the bend's further turn: it lies at most kMaxInheritedTurnRad of turn ahead.
  const double curvature = current.curvature.norm();
  if (curvature > 0.0) ahead = std::min(ahead, kMaxInheritedTurnRad / curvature);
  const double junction = here + travel * ahead;
  if (travel * junction < options_.min_section_length_radii * current.Radius()) return false;
  std::ostringstream reason;
  reason.precision(3);
  reason << "the section stopped explaining the features for " << unexplained_run_
         << " frames: " << 100.0 * gated_fraction << " % of " << considered
         << " failed the gate; tracks drift " << update.track_drift_px << " px (median of "
         << update.drift_tracks << ") from their wall points";
  unexplained_run_ = 0;
  anchors_.clear();
  StartSection(junction, travel, reason.str());
  return true;
}

void TubularEkf::StartSection(double junction, double travel, const std::string& reason) {
  const TubeSection& current = sections_.back().geometry;
  const double radius = current.Radius();
  // The new section points the way the camera travels, so a wall point behind its start
  // (negative axial coordinate) belongs to the sections before it.
  TubularEkfSection next;
  next.geometry.axis = travel * current.TangentAt(junction);
  // Straight until the features bend it: a section is started where the tube changed, where a
  // bend starts or ends.
  const std::size_t count = sections_.size();
  if (options_.extrapolate_turn && count >= 2 && !current.Curved()) {
    // Constant curvature: the turn from section count-2 to count-1 over the distance between
    // their starts, applied over the distance from the current start to the new junction.
    const TubeSection& before = sections_[count - 2].geometry;
    const double spacing = (current.start - before.start).norm();
    if (spacing > 1e-9) {
      const Eigen::AngleAxisd turn(Eigen::Quaterniond::FromTwoVectors(before.axis, current.axis));
      const Eigen::Vector3d turn_axis_angle = turn.angle() * turn.axis();
      const double fraction = std::min(2.0, std::abs(junction) / spacing);
      next.geometry.axis =
          (ExpRotation(fraction * turn_axis_angle) * next.geometry.axis).normalized();
    }
  }
  // The dataset's radius, the same prior as the first section's: a pipe keeps its radius, and a
  // section estimated from the one before would pass a misfit down the chain.
  next.geometry.log_radius = prior_log_radius_;
  next.geometry.start = current.CentrelinePoint(junction);
  next.first_frame = updates_;
  next.reason = reason;
  next.basis = OrthogonalBasis(next.geometry.axis);
  sections_.push_back(next);

  const int n = StateSize();
  Eigen::MatrixXd grown = Eigen::MatrixXd::Zero(n + kSectionSize, n + kSectionSize);
  grown.topLeftCorner(n, n) = covariance_;
  const double offset_sigma = options_.new_section_offset_sigma_radii * radius;
  for (int i = 0; i < 2; ++i) {
    grown(n + i, n + i) = offset_sigma * offset_sigma;
    grown(n + 2 + i, n + 2 + i) =
        options_.new_section_axis_sigma_rad * options_.new_section_axis_sigma_rad;
  }
  grown(n + 4, n + 4) = options_.new_section_radius_sigma * options_.new_section_radius_sigma;
  const double curvature_sigma = options_.curvature_sigma_radii / radius;
  for (int i = 5; i < 7; ++i) grown(n + i, n + i) = curvature_sigma * curvature_sigma;
  covariance_ = std::move(grown);
  while (static_cast<int>(sections_.size()) - first_active_ > options_.max_active_sections) {
    FreezeOldestActiveSection();
  }
}

void TubularEkf::FreezeOldestActiveSection() {
  // Marginalising a Gaussian: drop the section's rows and columns.
  const int offset = kCameraSize;
  const int n = StateSize();
  const int rest = n - offset - kSectionSize;
  Eigen::MatrixXd reduced(n - kSectionSize, n - kSectionSize);
  reduced.topLeftCorner(offset, offset) = covariance_.topLeftCorner(offset, offset);
  reduced.topRightCorner(offset, rest) = covariance_.topRightCorner(offset, rest);
  reduced.bottomLeftCorner(rest, offset) = covariance_.bottomLeftCorner(rest, offset);
  reduced.bottomRightCorner(rest, rest) = covariance_.bottomRightCorner(rest, rest);
  covariance_ = std::move(reduced);
  sections_[first_active_].active = false;
  ++first_active_;
}

}  // namespace pipescope
