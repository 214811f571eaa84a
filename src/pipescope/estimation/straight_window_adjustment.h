#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <optional>
#include <vector>

#include "pipescope/camera/camera.h"
#include "pipescope/estimation/cylinder_scale.h"

namespace pipescope {

// The sliding-window sparse bundle adjustment with a local straight cylinder of 001 §III-C:
//
//   epsilon = epsilon_I + tau epsilon_X                                   (eq. 2)
//
// with the fisheye reprojection error (eq. 3, FisheyeReprojectionError) over every observation
// in the window and the straight-cylinder error (eqs. 4-6, StraightCylinderError) over every
// point, the cylinder placed relative to the window's first pose, which is held fixed (the
// gauge). The supplied radius fixes the metric scale. Huber weighting on each term; outliers
// removed at several stages by the median absolute deviation of the signed Huber-weighted image
// errors u - u'. Given the previous window's axis (not in 001), the cylinder is tied to it
// (CylinderAxisPriorError) and the first pose's rotation is adjusted too.
struct StraightWindowOptions {
  double radius_m = 0.2;  // supplied pipe radius r
  double tau = 2.5e5;     // 001: tau = 2.5e5
  bool use_cylinder = true;
  double huber_px = 2.0;  // Huber threshold of the image term (and of sqrt(tau) e)
  // Outlier removal: after each of `stages` solves, observations whose signed Huber-weighted
  // error lies more than mad_factor * 1.4826 * MAD from the median are removed.
  int stages = 3;
  double mad_factor = 3.0;
  double min_mad_px = 0.1;  // MAD floor, so a near-perfect window keeps its observations
  int max_iterations_per_stage = 20;
  // Iterations of each stage that is followed by an outlier removal (all but the last): those
  // stages only need to separate the outliers, and after about 5 iterations from the start the
  // cost is within 0.1-0.5 % of where 20 leave it (the first stage used all 20, creeping along
  // a flat valley); the last stage still converges. Straight benchmark: distance error -0.06 ->
  // -0.05 %, ATE 0.0063 -> 0.0065 m (docs/fisheye_mapping.md, Speed), the odometry a third
  // cheaper.
  int max_iterations_before_outlier_removal = 5;
  // The prior tying the cylinder to the previous window's axis (CylinderAxisPriorError), when
  // the window has one: one sigma of angle, of offset at the first camera, or of the first
  // pose's turn (then free) counts as a pixel.
  double axis_prior_sigma_deg = 0.2;
  double axis_prior_sigma_m = 0.002;
  double first_rotation_sigma_deg = 1.0;
  // Ceres threads. One: `pipescope map` runs the windows on their own thread beside the
  // tracking, which takes the other core, and one thread sums in one order, so the poses are
  // the same to the last bit run to run (two differ by about 1e-13 m).
  int num_threads = 1;
};

// cam_from_world as Ceres parameter blocks: quaternion (w, x, y, z) and translation.
struct WindowPose {
  double rotation[4] = {1, 0, 0, 0};
  double translation[3] = {0, 0, 0};

  static WindowPose FromIsometry(const Eigen::Isometry3d& cam_from_world);
  Eigen::Isometry3d ToIsometry() const;
  // The pose as one 7-parameter block (quaternion, then translation), for the adjustments that
  // give Ceres each pose as a single block, and back.
  std::array<double, 7> ToBlock() const;
  void SetFromBlock(const std::array<double, 7>& block);
};

struct WindowObservation {
  int pose = 0;   // index into poses
  int point = 0;  // index into points
  Eigen::Vector2d pixel;
  bool inlier = true;  // cleared by the outlier removal
};

struct StraightWindow {
  std::vector<WindowPose> poses;  // poses[0] is the window's first pose P_m, held fixed
  std::vector<Eigen::Vector3d> points;
  std::vector<WindowObservation> observations;
  // Cylinder {gamma, beta, t_X, t_Y} relative to poses[0] (eq. 4); used as the initial value and
  // receives the fit.
  double cylinder[4] = {0, 0, 0, 0};
  // The previous window's axis in the same straight section, in the world: the pipe is one
  // straight cylinder, so this window's axis should continue it. With it, poses[0]'s rotation
  // is adjusted too (only its translation stays fixed).
  std::optional<PipeAxis> axis_prior;
};

struct StraightWindowSummary {
  int observations = 0;
  int outliers_removed = 0;
  // Reprojection RMS before and after, over the inlier observations of the points with two or
  // more of them (those the adjustment estimates).
  double initial_rms_px = 0.0;
  double final_rms_px = 0.0;
  double cylinder_rms_m = 0.0;  // RMS of sqrt(X~^2 + Y~^2) - r over the points, after
  double seconds = 0.0;
};

// Fits the cylinder alone to the points (poses and points fixed): a good start for the joint
// optimisation. Returns the RMS distance from the wall.
double FitStraightCylinder(const StraightWindowOptions& options, StraightWindow* window);

StraightWindowSummary OptimiseStraightWindow(const Camera& camera,
                                             const StraightWindowOptions& options,
                                             StraightWindow* window);

// The inlier observations of each of the window's points: the adjustment estimates the points
// with two or more; the others keep their start.
std::vector<int> InlierCounts(const StraightWindow& window);
// The same for any observations of `num_points` points (the T-intersection adjustment's too).
std::vector<int> InlierCounts(const std::vector<WindowObservation>& observations,
                              std::size_t num_points);

}  // namespace pipescope
