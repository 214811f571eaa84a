#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <unordered_map>
#include <vector>

#include "pipescope/camera/camera.h"
#include "pipescope/geometry/tube_section.h"

namespace pipescope {

// 004 §2: an extended Kalman filter over the camera (position, orientation, linear and angular
// velocity, eq. 2) and the tube's cylinder sections (eq. 3), with a constant-velocity model
// (eq. 6) and features back-projected onto the current section and re-projected into the next
// frame (eq. 7-9). Beyond 004:
// - Error-state form: orientations are perturbed on the right (q = q^ (x) Exp(dtheta)), a
//   section by 7 numbers (its start across the axis: 2, its axis: 2, log radius: 1, its
//   curvature across the axis: 2), so the filter carries no direction a straight cylinder
//   cannot show (it slides along and turns about its own axis).
// - A section may bend: a torus segment whose curvature is estimated (0: 004's cylinder), so a
//   bend is one section, not a chain of straight ones whose misfit pulls its angle short.
// - The previous frame's pose is cloned into the state before each prediction, so the
//   back-projection of eq. 9 uses frame k's estimate with its correlation to frame k+1.
// - Every camera model through Unproject/Project (004 is pinhole only).
// - Features are gated by their Mahalanobis distance (the filter's own outlier test) and the
//   update is iterated (Gauss-Newton on the back-projection's non-linearity).
// - A new section starts when the current one stops explaining the features: the share of
//   gated features stays high for several frames (the tube bends away from the section).
struct TubularEkfOptions {
  // 004 eq. 6: the zero-mean acceleration noise N_x (linear m/s^2, angular rad/s^2). Generous:
  // with a hundred features a frame, the motion comes from the images, not from this prior.
  double linear_acceleration_sigma = 1.0;
  double angular_acceleration_sigma = 3.0;
  // Localisation noise of a feature in each frame, px.
  double pixel_sigma = 0.5;
  // Mahalanobis gate on each feature's 2-D innovation (chi-square, 2 dof; 13.8 = 99.9 %).
  double gate_chi2 = 13.8;
  // Gauss-Newton iterations of the update (1 = plain EKF).
  int iterations = 2;
  // Fewest features an update needs; below it the frame keeps its prediction.
  int min_features = 8;
  // Most features an update uses (evenly over those that pass the gate): the update costs the
  // cube of their number.
  int max_features = 300;
  // Features whose wall point is farther along the section than this (radii) are not used: far
  // down a forward view they carry little parallax and most of a bend's misfit.
  double max_range_radii = 6.0;
  // A straight section misplaces the wall of a bend ahead by the bend's sagitta, which grows with
  // the square of the range; so a feature's pixel sigma grows alike: times
  // sqrt(1 + (range / (far_feature_radii * radius))^4). Near features count fully, far ones pin
  // the axis of a straight leg (a kink needs them) without pulling a bend's turn short. 0 = every
  // feature gets pixel_sigma.
  double far_feature_radii = 2.0;
  // Initial uncertainty of the velocities.
  double initial_speed_sigma = 0.5;          // m/s
  double initial_angular_speed_sigma = 1.0;  // rad/s
  // The first section: its axis and the camera's place across it are estimated, from these
  // initial uncertainties (the camera is first put on the axis, looking along it).
  double initial_axis_sigma_rad = 0.2;
  double initial_offset_sigma_radii = 0.3;
  // Relative uncertainty of the first section's radius (the prior on log rho that makes the run
  // metric). 0 = the radius is not known: it is held at its starting value and the run is up to
  // scale.
  double radius_prior_sigma = 0.01;
  // New sections (004 §2, the tube bends): the share of gated features above which a frame
  // counts as unexplained, the run of such frames that starts a section, the shortest section
  // (radii, along its axis from its start to the camera), and where the new section starts: this
  // many radii ahead of the camera along the current axis when the gate started it; when the
  // tracks' drift did, where the drifting tracks' wall points begin (their lowest tenth along
  // the axis), at least this far ahead. One radius: the drift is seen late where the far wall is
  // dark or small in the image (a fisheye), when the camera is already at the bend, and the
  // stretch of bend left to the section before pulls it (2 radii: bends 1.5-4.2 degrees short
  // through 001's fisheye, ATE 3.7-5.4 mm on the pinhole 90-degree bends against 1.7-2.6).
  double spawn_gated_fraction = 0.2;
  // ... or a frame whose tracks drift from their wall points: each track's wall point, placed on
  // the section when the track was first seen, is projected into every later frame; when the
  // median distance to where the track is, over the tracks `track_min_age_frames` to
  // `track_max_age_frames` old (older ones carry the tracker's own drift),
  // exceeds `spawn_track_drift_px`, the section no longer explains the features. Frame-to-frame
  // innovations see a bend only through a few millimetres of parallax; a track's age multiplies
  // the baseline.
  int track_min_age_frames = 10;
  int track_max_age_frames = 30;
  double spawn_track_drift_px = 5.0;
  int spawn_frames = 3;
  double min_section_length_radii = 1.0;
  double spawn_lookahead_radii = 1.0;
  // After a straight section, a new section's axis first continues the turn from the section
  // before the current one to the current one (scaled by their lengths), instead of the current
  // axis: in a bend the filter then corrects a guess centred on the curve rather than lagging
  // behind it. (After a bending section it leaves along its tangent.)
  bool extrapolate_turn = true;
  // A new section's initial uncertainty: its start across the axis (radii), its axis direction,
  // its relative radius about the radius given at the start (the dataset's: a pipe keeps its
  // radius). The radius is estimated with that prior; left freer (0.05), the straight sections
  // fitted to a bend come out narrow (its outer wall ahead closes in on their axes), and since
  // the radius sets the scale, the distance through the bend short: 0.5-6.9 % on tube-bend's
  // nine bend runs (docs/ekf.md). (Holding the start to the junction, 0.002 radii, turns bends
  // further but shortens the distance through them: docs/ekf.md.)
  double new_section_offset_sigma_radii = 0.05;
  double new_section_axis_sigma_rad = 0.15;
  double new_section_radius_sigma = 0.01;
  // Prior uncertainty of each section's curvature (times the radius: one over the bend's radius
  // in radii) about 0: every section starts straight and may bend as a torus segment. 0 =
  // straight sections only (004).
  double curvature_sigma_radii = 0.3;
  // Sections kept in the state; older ones are frozen (dropped from the state with their last
  // estimate) so the filter's size stays bounded however long the tube.
  int max_active_sections = 5;
};

// One feature seen in the previous frame (its unit bearing there) and found in this one, with
// the id of its track (-1: none), by which the filter follows how well the section explains it.
struct TubularEkfMatch {
  Eigen::Vector3d previous_bearing;
  Eigen::Vector2d pixel;
  long track_id = -1;
};

// What one update did.
struct TubularEkfUpdate {
  int matches = 0;
  int used = 0;           // passed the gate and updated the state
  int gated = 0;          // failed the Mahalanobis gate
  int unplaced = 0;       // no wall point (ray along the axis, beyond the range, behind the camera)
  double mean_nis = 0.0;  // mean normalised innovation squared of the used features (2 expected)
  double rms_innovation_px = 0.0;
  // Median drift of the old enough tracks from their wall points (px); -1 when none is old enough.
  double track_drift_px = -1.0;
  int drift_tracks = 0;
  bool updated = false;  // false: too few features; the frame keeps its prediction
  bool spawned_section = false;
};

// A section as the filter holds it: the geometry, and whether it is still in the state.
struct TubularEkfSection {
  TubeSection geometry;
  // The two directions across the axis in which the filter perturbs the start and the axis. Set
  // when the section starts and turned with the axis at each update (never recomputed from
  // scratch), so the covariance keeps meaning the same directions.
  Eigen::Matrix<double, 3, 2> basis = Eigen::Matrix<double, 3, 2>::Identity();
  bool active = true;
  int first_frame = 0;  // the update count when it was started
  std::string reason;   // why it was started
};

class TubularEkf {
 public:
  // The camera starts at `world_from_cam` at rest (velocities 0 with the initial uncertainties)
  // on the axis of the first section, which runs along `axis_in_camera` (a unit vector in the
  // camera frame) with radius `radius` (metres; 1 when the run is up to scale).
  TubularEkf(const Camera& camera, const Eigen::Isometry3d& world_from_cam,
             const Eigen::Vector3d& axis_in_camera, double radius,
             const TubularEkfOptions& options);

  // 004 eq. 6 over dt seconds, after cloning the current pose as the previous frame's.
  void Predict(double dt);
  // 004 eq. 9: updates with the features of the previous frame found in this one, then starts a
  // new section if the current one has stopped explaining them.
  TubularEkfUpdate Update(const std::vector<TubularEkfMatch>& matches);

  Eigen::Isometry3d WorldFromCam() const;
  const Eigen::Vector3d& Velocity() const { return velocity_; }
  const Eigen::Vector3d& AngularVelocity() const { return angular_velocity_; }
  const std::vector<TubularEkfSection>& Sections() const { return sections_; }
  const Eigen::MatrixXd& Covariance() const { return covariance_; }
  int StateSize() const { return static_cast<int>(covariance_.rows()); }

  // The pixel at which a bearing of the previous frame is predicted in this one, and its
  // Jacobian with respect to the error state (2 x StateSize()); false when it meets no wall.
  // Public for the finite-difference test.
  // `variance`, when given, receives the variance of each innovation coordinate of this feature
  // (InnovationVariance).
  bool PredictPixel(const Eigen::Vector3d& previous_bearing, Eigen::Vector2d* pixel,
                    Eigen::MatrixXd* jacobian, double* variance = nullptr) const;
  // The variance of one innovation coordinate (both frames' localisation) of a feature whose
  // wall point lies `range` metres ahead on a section of radius `radius` (far_feature_radii).
  double InnovationVariance(double range, double radius) const;
  // Applies an error-state correction (size StateSize()); public for the same test.
  void Inject(const Eigen::VectorXd& delta);

  // Error-state layout.
  static constexpr int kPosition = 0;
  static constexpr int kRotation = 3;
  static constexpr int kVelocity = 6;
  static constexpr int kAngularVelocity = 9;
  static constexpr int kPreviousPosition = 12;
  static constexpr int kPreviousRotation = 15;
  static constexpr int kCameraSize = 18;
  static constexpr int kSectionSize = 7;

 private:
  // The nominal state, saved and restored by the iterated update.
  struct Nominal {
    Eigen::Vector3d position, velocity, angular_velocity, previous_position;
    Eigen::Quaterniond rotation, previous_rotation;
    std::vector<TubularEkfSection> sections;
  };
  Nominal SaveNominal() const;
  void RestoreNominal(const Nominal& nominal);
  // The section a previous-frame feature's wall point lies on: the newest whose start is behind
  // it. -1 when the ray meets no wall or the point lies beyond the range.
  // `range` receives the wall point's distance ahead along the section's centreline.
  int SectionOfRay(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                   double* range = nullptr) const;
  int StateOffsetOfSection(int section) const;
  // Starts a section when the current one has stopped explaining the features; true if it did.
  bool MaybeStartSection(const TubularEkfUpdate& update);
  // Starts a section at `junction` along the current axis (from its start), pointing `travel`
  // (+1 or -1) times the current axis.
  void StartSection(double junction, double travel, const std::string& reason);
  void FreezeOldestActiveSection();

  // Projects each track's wall point into this frame (tracks first seen now get their point),
  // fills update->track_drift_px, and forgets the tracks not seen.
  void MeasureTrackDrift(const std::vector<TubularEkfMatch>& matches, TubularEkfUpdate* update);

  struct TrackAnchor {
    Eigen::Vector3d wall_point;
    int first_update = 0;
  };
  const Camera& camera_;
  TubularEkfOptions options_;
  std::unordered_map<long, TrackAnchor> anchors_;
  // The last frame's measured tracks: their wall point's axial coordinate on the newest section
  // and their drift (px); where the drifting ones begin is where the tube turns.
  std::vector<std::pair<double, double>> track_drifts_;
  Eigen::Vector3d position_;
  Eigen::Quaterniond rotation_;                                 // world_from_cam
  Eigen::Vector3d velocity_ = Eigen::Vector3d::Zero();          // world frame
  Eigen::Vector3d angular_velocity_ = Eigen::Vector3d::Zero();  // camera frame
  Eigen::Vector3d previous_position_;
  Eigen::Quaterniond previous_rotation_;
  std::vector<TubularEkfSection> sections_;
  int first_active_ = 0;  // sections_[first_active_..] are in the state
  Eigen::MatrixXd covariance_;
  int updates_ = 0;
  int unexplained_run_ = 0;
  double prior_log_radius_ = 0.0;  // the radius given at the start (the dataset's)
};

// Two unit vectors orthogonal to `axis` and to each other: the directions in which a section's
// start and axis are perturbed.
Eigen::Matrix<double, 3, 2> OrthogonalBasis(const Eigen::Vector3d& axis);

}  // namespace pipescope
