#include "pipescope/estimation/keyframe_odometry.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "pipescope/estimation/cylinder_scale.h"
#include "pipescope/estimation/fisheye_reprojection_error.h"
#include "pipescope/estimation/least_squares_solve.h"
#include "pipescope/geometry/multiview_triangulation.h"
#include "pipescope/geometry/sphere_relative_pose.h"
#include "pipescope/util/median.h"

namespace pipescope {
namespace {

// The angle between a feature's bearings in two key frames once their relative rotation
// (cam_this_from_cam_previous) is taken out: what the translation moved it.
double Parallax(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& previous_bearing,
                const Eigen::Vector3d& bearing) {
  return std::acos(std::clamp(previous_bearing.dot(rotation.transpose() * bearing), -1.0, 1.0));
}

// The key frame's pose refined on the reprojection errors of the already triangulated points
// (Huber), the points held fixed.
void RefinePose(const Camera& camera, const std::vector<Eigen::Vector3d>& points,
                const std::vector<Eigen::Vector2d>& pixels, double huber_px,
                Eigen::Isometry3d* cam_from_world) {
  WindowPose pose = WindowPose::FromIsometry(*cam_from_world);
  std::vector<Eigen::Vector3d> fixed = points;
  ceres::Problem problem;
  for (std::size_t k = 0; k < fixed.size(); ++k) {
    problem.AddResidualBlock(
        FisheyeReprojectionError::Create(camera.ModelId(), camera.Params(), pixels[k]),
        new ceres::HuberLoss(huber_px), pose.rotation, pose.translation, fixed[k].data());
    problem.SetParameterBlockConstant(fixed[k].data());
  }
  problem.SetManifold(pose.rotation, new ceres::QuaternionManifold);
  if (SolveLeastSquares(&problem, ceres::DENSE_QR, 10, 0).usable) {
    *cam_from_world = pose.ToIsometry();
  }
}

}  // namespace

void KeyframeOdometry::Add(TrackedKeyframe keyframe, const KeyframeSection& section) {
  const int k = static_cast<int>(tracked_.size());
  tracked_.push_back(std::move(keyframe));
  sections_.push_back(section);
  cam_from_world_.push_back(Eigen::Isometry3d::Identity());
  steps_.emplace_back();
  AddObservations(k);
  if (k > 0) EstimatePose(k);
  Triangulate(k);
  const int in_section = k - section.first_keyframe + 1;
  if (in_section >= 3 && (in_section % options_.window_interval == 0 || section.last_in_section)) {
    // A window never spans a tracking reset: no track links the two sides.
    const int first =
        std::max({section.first_keyframe, segment_start_, k - options_.window_size + 1});
    // A shorter window (just after a reset) fits its cylinder to too few key frames.
    if (k - first + 1 >= options_.min_window_keyframes) {
      AdjustWindow(first, k, section.section, section.view_class == PipeViewClass::kStraight);
    }
  }
}

void KeyframeOdometry::AddObservations(int k) {
  for (const TrackedFeature& feature : tracked_[k].features) {
    tracks_[feature.track_id].observations.push_back(
        {k, Eigen::Vector2d(feature.pixel.x, feature.pixel.y), feature.bearing});
  }
}

// Five-point (here: RANSAC on the sphere) direction, then the step length: in a straight
// section from the pipe radius (the two-view points put on the wall, eq. 6, with the axis from
// the last window's cylinder), otherwise from the section's earlier structure; then a
// pose-only refinement on the triangulated points.
void KeyframeOdometry::EstimatePose(int k) {
  const TrackedKeyframe& keyframe = tracked_[k];
  const int section = sections_[k].section;
  const bool straight = sections_[k].view_class == PipeViewClass::kStraight;
  if (section != axis_section_) {
    // A new section: until its first window fits a cylinder, the axis is taken as the
    // optical axis of the camera that enters it (the camera looks along the pipe).
    axis_world_.point = cam_from_world_[k - 1].inverse().translation();
    axis_world_.direction = cam_from_world_[k - 1].rotation().transpose().col(2);
    axis_section_ = section;
    axis_keyframe_ = k;
  }
  const int frames = keyframe.frame_index - tracked_[k - 1].frame_index;
  // A crawler moves at a nearly constant speed: the recent key-frame steps' median speed.
  const double predicted = UpperMedian(recent_speeds_) * frames;
  if (!keyframe.has_previous) {
    // Tracking started over: no correspondence links this key frame to the previous one, so
    // it continues along the last step's direction at the recent speed (copying the pose
    // would lose the distance travelled in the gap).
    Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
    step.translation() = predicted * last_direction_;
    cam_from_world_[k] = step * cam_from_world_[k - 1];
    segment_start_ = k;
    return;
  }
  // A crawler that stands still: the features moved only by the rotation, so the translation's
  // direction is noise. The camera keeps its place and turns as measured.
  if (MedianParallax(k) < options_.stationary_parallax_rad) {
    Eigen::Isometry3d turn = Eigen::Isometry3d::Identity();
    turn.linear() = keyframe.relative_pose.rotation;
    cam_from_world_[k] = turn * cam_from_world_[k - 1];
    steps_[k].stationary = true;
    return;
  }
  // The crawler's direction of travel is nearly fixed in the camera frame (the camera is
  // mounted on it, looking along the pipe): a translation more than max_step_direction_change_deg
  // off the recent steps' mean direction (at the start, the optical axis; either sign) is a
  // wrong relative pose (RANSAC on few matches trades a sideways translation for a few
  // degrees of rotation). The step then continues the recent motion without turning, and
  // the next window places it. Unlike the pipe axis this reference depends on no window.
  const Eigen::Vector3d reference = ReferenceDirection();
  if (std::abs(keyframe.relative_pose.translation.dot(reference)) <
      std::cos(options_.max_step_direction_change_deg * M_PI / 180.0)) {
    steps_[k].direction_rejected = true;
    Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
    step.translation() = predicted * (recent_directions_.empty() ? last_direction_ : reference);
    cam_from_world_[k] = step * cam_from_world_[k - 1];
    return;
  }
  const Eigen::Matrix3d& rotation = keyframe.relative_pose.rotation;
  const Eigen::Vector3d& direction = keyframe.relative_pose.translation;
  std::vector<double> ratios;
  std::vector<Eigen::Vector3d> unit_points, points;
  std::vector<Eigen::Vector2d> pixels;
  for (const TrackedFeature& feature : keyframe.features) {
    const Track& track = tracks_[feature.track_id];
    const Observation* previous_observation = InPreviousKeyframe(track, k);
    if (!previous_observation) continue;
    const Observation& previous = *previous_observation;
    if (track.has_point) {
      points.push_back(track.point);
      pixels.emplace_back(feature.pixel.x, feature.pixel.y);
    }
    double depth_i, depth_j;
    if (Parallax(rotation, previous.bearing, feature.bearing) <= options_.min_scale_parallax_rad ||
        !TriangulateDepthsMidpoint(rotation, direction, previous.bearing, feature.bearing, &depth_i,
                                   &depth_j) ||
        depth_i <= 0 || depth_j <= 0) {
      continue;
    }
    unit_points.push_back(depth_i * previous.bearing);
    if (track.has_point) {
      ratios.push_back((cam_from_world_[k - 1] * track.point).norm() / depth_i);
    }
  }
  // A step length more than max_step_change times off the recent speed comes from a bad
  // axis or bad structure.
  const auto plausible = [&](double length) {
    return length > 0.0 && (predicted <= 0.0 || (length < options_.max_step_change * predicted &&
                                                 length * options_.max_step_change > predicted));
  };
  double from_radius = 0.0;
  PipeAxis axis = AxisInCamera(k - 1);
  // The window axis goes stale with the accumulated rotation when no window has been applied
  // for a window's length: then the axis is fitted with the scale to the step's own points.
  const bool fit_axis =
      options_.fit_axis_per_step || k - axis_keyframe_ > options_.stale_axis_keyframes;
  if (straight && static_cast<int>(unit_points.size()) >= options_.min_cylinder_scale_points) {
    from_radius = fit_axis ? FitScaleAndAxis(unit_points, options_.window.radius_m, &axis)
                           : ScaleFromCylinderRadius(unit_points, axis, options_.window.radius_m);
  }
  double scale = predicted;
  if (plausible(from_radius)) {
    scale = from_radius;
    if (fit_axis) {
      const Eigen::Isometry3d world_from_previous = cam_from_world_[k - 1].inverse();
      axis_world_.point = world_from_previous * axis.point;
      axis_world_.direction = world_from_previous.linear() * axis.direction;
    }
    steps_[k].points_used = static_cast<int>(unit_points.size());
  } else if (ratios.size() >= 5 && plausible(UpperMedian(ratios))) {
    scale = UpperMedian(ratios);
    steps_[k].points_used = static_cast<int>(ratios.size());
  }
  Eigen::Isometry3d cam_k_from_previous = Eigen::Isometry3d::Identity();
  cam_k_from_previous.linear() = rotation;
  cam_k_from_previous.translation() = scale * direction;
  cam_from_world_[k] = cam_k_from_previous * cam_from_world_[k - 1];
  if (options_.refine_pose_on_structure && points.size() >= 10) {
    RefinePose(camera_, points, pixels, options_.window.huber_px, &cam_from_world_[k]);
  }
  const Eigen::Vector3d step =
      (cam_from_world_[k] * cam_from_world_[k - 1].inverse()).translation();
  if (step.norm() > 0.0) {
    last_direction_ = step.normalized();
    recent_directions_.push_back(last_direction_);
    if (static_cast<int>(recent_directions_.size()) > options_.speed_history) {
      recent_directions_.erase(recent_directions_.begin());
    }
  }
  recent_speeds_.push_back(step.norm() / std::max(1, frames));
  if (static_cast<int>(recent_speeds_.size()) > options_.speed_history) {
    recent_speeds_.erase(recent_speeds_.begin());
  }
}

// The track's observation in key frame k - 1, when the track goes on into key frame k.
const KeyframeOdometry::Observation* KeyframeOdometry::InPreviousKeyframe(const Track& track,
                                                                          int k) {
  if (track.observations.size() < 2) return nullptr;
  const Observation& previous = track.observations[track.observations.size() - 2];
  return previous.keyframe == k - 1 ? &previous : nullptr;
}

// Median over key frame k's features tracked from key frame k-1 of the angle between their two
// bearings with the relative rotation taken out: what the translation moved them; infinite
// without any such feature (nothing shows that the camera stood still).
double KeyframeOdometry::MedianParallax(int k) const {
  const TrackedKeyframe& keyframe = tracked_[k];
  const Eigen::Matrix3d& rotation = keyframe.relative_pose.rotation;
  std::vector<double> parallax;
  for (const TrackedFeature& feature : keyframe.features) {
    const Observation* previous = InPreviousKeyframe(tracks_.at(feature.track_id), k);
    if (previous) parallax.push_back(Parallax(rotation, previous->bearing, feature.bearing));
  }
  return parallax.empty() ? std::numeric_limits<double>::infinity() : UpperMedian(parallax);
}

// The mean of the recent steps' translation directions (cam_k_from_previous), each turned to
// the sense of the latest one, or the optical axis before the first step. The direction is a
// line: a crawler that reverses moves along the same pipe, and a plain mean of steps on both
// sides of the turnaround is near zero, so its direction is noise, and every step after it
// would be rejected (and, rejected, never renew it).
Eigen::Vector3d KeyframeOdometry::ReferenceDirection() const {
  if (recent_directions_.empty()) return Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d& latest = recent_directions_.back();
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& direction : recent_directions_) {
    sum += direction.dot(latest) < 0.0 ? -direction : direction;
  }
  return sum.normalized();  // at least |latest| = 1
}

// Length of the camera path through key frames first..last.
double KeyframeOdometry::PathLength(int first, int last) const {
  return PathLength(std::vector<Eigen::Isometry3d>(cam_from_world_.begin() + first,
                                                   cam_from_world_.begin() + last + 1));
}
double KeyframeOdometry::PathLength(const std::vector<Eigen::Isometry3d>& cam_from_world) {
  double length = 0.0;
  for (std::size_t k = 1; k < cam_from_world.size(); ++k) {
    length +=
        (cam_from_world[k].inverse().translation() - cam_from_world[k - 1].inverse().translation())
            .norm();
  }
  return length;
}

// The fastest key-frame step of a window (poses from key frame `first` on) over its median
// speed, in metres a frame. The degenerate solution that keeps the path length puts the
// window's travel into one or two steps and leaves the cameras together elsewhere.
double KeyframeOdometry::MaxSpeedOverMedian(const std::vector<Eigen::Isometry3d>& cam_from_world,
                                            int first) const {
  std::vector<double> speeds;
  for (std::size_t k = 1; k < cam_from_world.size(); ++k) {
    const int frames = tracked_[first + k].frame_index - tracked_[first + k - 1].frame_index;
    speeds.push_back(
        (cam_from_world[k].inverse().translation() - cam_from_world[k - 1].inverse().translation())
            .norm() /
        std::max(1, frames));
  }
  const double median = UpperMedian(speeds);
  const double fastest = *std::max_element(speeds.begin(), speeds.end());
  return median > 0.0 ? fastest / median : std::numeric_limits<double>::infinity();
}

// The current pipe axis in key frame k's camera frame.
PipeAxis KeyframeOdometry::AxisInCamera(int k) const {
  PipeAxis axis;
  axis.point = cam_from_world_[k] * axis_world_.point;
  axis.direction = cam_from_world_[k].linear() * axis_world_.direction;
  return axis;
}

void KeyframeOdometry::Triangulate(int k) {
  const double min_angle = options_.min_triangulation_angle_deg * M_PI / 180.0;
  for (const TrackedFeature& feature : tracked_[k].features) {
    Track& track = tracks_[feature.track_id];
    if (track.has_point || track.observations.size() < 2) continue;
    const Observation& first = track.observations.front();
    const Observation& last = track.observations.back();
    const Eigen::Isometry3d last_from_first =
        cam_from_world_[last.keyframe] * cam_from_world_[first.keyframe].inverse();
    const Eigen::Vector3d ray_first_in_last = last_from_first.linear() * first.bearing;
    if (std::acos(std::clamp(ray_first_in_last.dot(last.bearing), -1.0, 1.0)) < min_angle) {
      continue;
    }
    double depth_first, depth_last;
    if (!TriangulateDepthsMidpoint(last_from_first.linear(), last_from_first.translation(),
                                   first.bearing, last.bearing, &depth_first, &depth_last) ||
        depth_first <= 0 || depth_last <= 0) {
      continue;
    }
    const Eigen::Vector3d point =
        cam_from_world_[first.keyframe].inverse() * (depth_first * first.bearing);
    if (ReprojectionErrorPx(camera_, cam_from_world_[first.keyframe], point, first.pixel) >
            options_.max_triangulation_error_px ||
        ReprojectionErrorPx(camera_, cam_from_world_[last.keyframe], point, last.pixel) >
            options_.max_triangulation_error_px) {
      continue;
    }
    track.has_point = true;
    track.point = point;
  }
}

// The track's point from its observations in key frames first..last on the current poses
// (multi-view midpoint on the bearings), when the rays part by at least the triangulation
// angle; false otherwise.
bool KeyframeOdometry::TriangulateInWindow(const std::vector<const Observation*>& observations,
                                           Eigen::Vector3d* point) const {
  std::vector<BearingObservation> rays;
  for (const Observation* observation : observations) {
    rays.push_back({cam_from_world_[observation->keyframe], observation->bearing});
  }
  const Eigen::Vector3d first_ray =
      rays.front().cam_from_world.linear().transpose() * rays.front().bearing;
  const Eigen::Vector3d last_ray =
      rays.back().cam_from_world.linear().transpose() * rays.back().bearing;
  if (std::acos(std::clamp(first_ray.dot(last_ray), -1.0, 1.0)) <
      options_.min_triangulation_angle_deg * M_PI / 180.0) {
    return false;
  }
  return TriangulateMidpoint(rays, point);
}

void KeyframeOdometry::AdjustWindow(int first, int last, int section, bool cylinder) {
  StraightWindow window;
  for (int k = first; k <= last; ++k) {
    window.poses.push_back(WindowPose::FromIsometry(cam_from_world_[k]));
  }
  std::vector<Track*> window_tracks;
  std::vector<const Observation*> in_window;
  for (auto& [id, track] : tracks_) {
    in_window.clear();
    for (const Observation& observation : track.observations) {
      if (observation.keyframe >= first && observation.keyframe <= last) {
        in_window.push_back(&observation);
      }
    }
    if (in_window.size() < 2) continue;
    Eigen::Vector3d point = track.point;
    // Every track seen twice in the window is triangulated anew from the current poses
    // (001 §III-C re-estimates the window's scene points); a point triangulated once, from
    // two early observations on the chained poses, would carry that chain's error into
    // the adjustment.
    if (options_.retriangulate_in_window ? !TriangulateInWindow(in_window, &point)
                                         : !track.has_point) {
      continue;
    }
    const int point_index = static_cast<int>(window.points.size());
    window.points.push_back(point);
    window_tracks.push_back(&track);
    for (const Observation* observation : in_window) {
      // Observations far from the start (mismatches) would pull the solution before the
      // MAD stages could remove them.
      const bool inlier =
          !options_.retriangulate_in_window ||
          ReprojectionErrorPx(camera_, cam_from_world_[observation->keyframe], point,
                              observation->pixel) < options_.max_window_start_error_px;
      window.observations.push_back(
          {observation->keyframe - first, point_index, observation->pixel, inlier});
    }
  }
  if (window.points.size() < 10) return;
  // A straight section's window fits the cylinder unless the options turn it off.
  const bool fits_cylinder = cylinder && options_.window.use_cylinder;
  if (fits_cylinder && options_.axis_prior && window_axis_section_ == section) {
    window.axis_prior = window_axis_world_;
  }
  StraightWindowOptions window_options = options_.window;
  window_options.use_cylinder = fits_cylinder;
  OdometryWindowRecord record;
  record.section = section;
  record.first_keyframe = first;
  record.last_keyframe = last;
  record.points = static_cast<int>(window.points.size());
  record.straight = cylinder;
  record.cylinder = fits_cylinder;
  record.summary = OptimiseStraightWindow(camera_, window_options, &window);
  // The window's path length must stay about what the radius-fixed steps gave: a window that
  // shrinks it has fallen into the degenerate solution (cameras together, the informative
  // observations removed as outliers, points on the wall along their rays); it is dropped.
  std::vector<Eigen::Isometry3d> adjusted;
  for (const WindowPose& pose : window.poses) adjusted.push_back(pose.ToIsometry());
  const double length_ratio = PathLength(adjusted) / std::max(1e-12, PathLength(first, last));
  record.length_ratio = length_ratio;
  if (record.summary.final_rms_px >= options_.max_window_rms_px) {
    record.rejection = "image rms";
  } else if (fits_cylinder && record.summary.cylinder_rms_m >=
                                  options_.max_window_cylinder_rms * options_.window.radius_m) {
    record.rejection = "cylinder rms";
  } else if (length_ratio * options_.max_window_length_change < 1.0 ||
             length_ratio > options_.max_window_length_change) {
    record.rejection = "path length";
  } else if (MaxSpeedOverMedian(adjusted, first) > options_.max_window_speed_ratio) {
    record.rejection = "step spread";
  }
  if (!record.rejection.empty()) {
    windows_.push_back(record);
    return;
  }
  for (int k = first; k <= last; ++k) cam_from_world_[k] = adjusted[k - first];
  const std::vector<int> inliers = InlierCounts(window);
  for (std::size_t p = 0; p < window_tracks.size(); ++p) {
    if (inliers[p] < 2) continue;  // not estimated by the window
    window_tracks[p]->point = window.points[p];
    window_tracks[p]->has_point = true;
  }
  if (fits_cylinder && section == axis_section_) {
    // The fitted cylinder (eq. 4, relative to the window's first pose) gives the axis that
    // fixes the following step lengths.
    const PipeAxis axis = StraightCylinderAxis(window.cylinder);
    const Eigen::Isometry3d world_from_first = cam_from_world_[first].inverse();
    axis_world_.point = world_from_first * axis.point;
    axis_world_.direction = world_from_first.linear() * axis.direction;
    axis_keyframe_ = last;
    window_axis_world_ = axis_world_;  // the next window's prior
    window_axis_section_ = section;
  }
  windows_.push_back(record);
}

std::vector<SparsePoint> KeyframeOdometry::Points() const {
  std::vector<SparsePoint> points;
  for (const auto& [id, track] : tracks_) {
    if (!track.has_point) continue;
    points.push_back({track.point, sections_[track.observations.front().keyframe].section, id});
  }
  return points;
}

std::vector<std::vector<KeyframeOdometry::Observation>> KeyframeOdometry::TracksIn(
    int first, int last, int min_observations, std::vector<long>* ids) const {
  std::vector<std::vector<Observation>> tracks;
  if (ids) ids->clear();
  for (const auto& [id, track] : tracks_) {
    std::vector<Observation> in_range;
    for (const Observation& observation : track.observations) {
      if (observation.keyframe >= first && observation.keyframe <= last) {
        in_range.push_back(observation);
      }
    }
    if (static_cast<int>(in_range.size()) < min_observations) continue;
    tracks.push_back(std::move(in_range));
    if (ids) ids->push_back(id);
  }
  return tracks;
}

int KeyframeOdometry::FirstKeyframeOfTrack(long track_id) const {
  const auto found = tracks_.find(track_id);
  if (found == tracks_.end() || found->second.observations.empty()) return -1;
  return found->second.observations.front().keyframe;
}

}  // namespace pipescope
