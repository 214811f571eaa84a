#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "pipescope/io/trajectory.h"
#include "pipescope/synthetic/centreline_path.h"

namespace pipescope {

// How the robot drives along its route. Amplitudes are of smooth random functions of the
// distance driven (not of time), so a robot that stops is exactly still.
struct MotionOptions {
  double fps = 7.5;
  int frames = 100;
  double speed_m_s = 0.01;
  double speed_variation = 0.1;  // relative amplitude of smooth speed changes
  int stop_count = 0;            // stops spread over the run
  double stop_duration_s = 2.0;
  double start_s_m = 0.0;  // where on the path the run starts
  double travel_m = 1.0;   // distance driven before turning back (out-and-back) or stopping
  bool out_and_back = false;
  double lateral_offset_m = 0.0;  // offset of the robot from the centreline, per axis
  double roll_deg = 0.0;          // roll about the pipe axis
  double wobble_deg = 0.0;        // pitch and yaw wobble
  double heading_deg = 0.0;       // extra slow yaw (a robot turning on the culvert floor, 003)
  double wobble_wavelength_m = 0.5;
  double wander_wavelength_m = 0.0;  // of the lateral offset; 0: wobble_wavelength_m
  std::uint64_t seed = 1;
};

// Samples a sum of sinusoids with random phases: a smooth deterministic function in [-1, 1].
class SmoothNoise {
 public:
  SmoothNoise(std::uint64_t seed, double wavelength);
  double operator()(double u) const;

 private:
  static constexpr int kTerms = 4;
  double frequency_[kTerms];
  double phase_[kTerms];
  double amplitude_[kTerms];
};

// Camera poses of a simulated run: the robot body follows the path (z forward along the
// tangent, y towards world "down" +Y, x = y × z), displaced and rotated by the motion noise; the
// camera is mounted on the body by `body_from_cam`.
class TrajectoryGenerator {
 public:
  TrajectoryGenerator(CentrelinePath path, MotionOptions options, Eigen::Isometry3d body_from_cam);

  // world_from_cam at time t (seconds from the first frame).
  Eigen::Isometry3d WorldFromCam(double t) const;
  // The nominal body pose (no offsets or wobble) at arc length s: the white-card and reference
  // views use it.
  Eigen::Isometry3d NominalWorldFromCam(double s) const;
  // Arc length along the path at time t.
  double ArcLength(double t) const;
  // The frame poses, timestamps index / fps.
  Trajectory Frames() const;

  const CentrelinePath& path() const { return path_; }

 private:
  Eigen::Isometry3d BodyFrame(double s) const;
  // Arc length and distance driven at time t, interpolated from the integrated table.
  void Sample(double t, double* s, double* driven) const;

  CentrelinePath path_;
  MotionOptions options_;
  Eigen::Isometry3d body_from_cam_;
  double table_dt_;
  std::vector<double> arc_length_;  // s at k * table_dt_
  std::vector<double> driven_;      // cumulative |ds|
  SmoothNoise speed_noise_, offset_x_, offset_y_, roll_, pitch_, yaw_, heading_;
};

}  // namespace pipescope
