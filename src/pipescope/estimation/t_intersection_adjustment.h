#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "pipescope/camera/camera.h"
#include "pipescope/estimation/straight_window_adjustment.h"
#include "pipescope/geometry/t_intersection.h"

namespace pipescope {

// The bundle adjustment of one T-intersection, 001 §III-D: every camera pose P_T in the T
// between P_r (the last pose of the section before it) and P_b (the first pose of the section
// after it), the T's scene points and the model Phi (geometry/t_intersection.h) minimise eq. 2,
// the fisheye reprojection error (eq. 3) plus tau times the distance of each point from the
// wall of the cylinder whose surface is nearer (eq. 6, Fig. 4c), with the same tau, Huber
// weighting and MAD outlier removal as the straight windows. The two cylinders C_r and C_b were
// fitted to the ends of the straight sections (001 Fig. 4a) and stay as they are; P_r is the
// gauge; P_b is not free but placed by Phi (eq. 8), so the images seen from it measure Phi.
struct TIntersectionOptions {
  double radius_m = 0.2;
  double tau = 2.5e5;
  double huber_px = 2.0;
  int stages = 3;
  double mad_factor = 3.0;
  double min_mad_px = 0.1;
  int max_iterations_per_stage = 50;
  int num_threads = 1;
  // Hold phi at its initial value (a fitting whose angle the user gives): the images leave the
  // angle of a T poorly measured (docs/fisheye_mapping.md, "Turns confirmed or not").
  bool hold_phi = false;
};

struct TIntersectionProblem {
  // poses[0] is P_r (held), poses.back() is P_b (set from the model), those between are P_T.
  std::vector<WindowPose> poses;
  double red_cylinder[4] = {0, 0, 0, 0};                            // C_r relative to P_r (eq. 4)
  double blue_cylinder[4] = {0, 0, 0, 0};                           // C_b relative to P_b
  double model[kTIntersectionParameters] = {0, 0, 0, 0, M_PI / 2};  // initial value, receives Phi
  std::vector<Eigen::Vector3d> points;
  std::vector<WindowObservation> observations;  // `pose` indexes poses
};

struct TIntersectionSummary {
  int observations = 0;
  int outliers_removed = 0;
  double initial_rms_px = 0.0;
  double final_rms_px = 0.0;
  double cylinder_rms_m = 0.0;  // RMS distance from the nearer wall over the estimated points
  int red_points = 0;           // estimated points on each cylinder at the end
  int blue_points = 0;
  bool usable = false;  // Ceres found a usable solution
  double seconds = 0.0;
  std::string schur_structure;       // the last solve's (LeastSquaresOutcome::schur_structure)
  std::vector<int> stage_iterations;  // Levenberg-Marquardt iterations of each stage's solve
};

// Solves the problem in place: the model, poses[1 ..] and the points. poses.back() is set from
// the model whatever it held.
TIntersectionSummary OptimiseTIntersection(const Camera& camera,
                                           const TIntersectionOptions& options,
                                           TIntersectionProblem* problem);

// P_b's cam_from_world from the model: inv(Q) P_r.
Eigen::Isometry3d BlueCamFromWorld(const TIntersectionProblem& problem);

}  // namespace pipescope
