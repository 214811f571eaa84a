#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "pipescope/camera/camera.h"
#include "pipescope/estimation/keyframe_odometry.h"
#include "pipescope/estimation/t_intersection_adjustment.h"
#include "pipescope/image/pipe_view_classification.h"

namespace pipescope {

struct TIntersectionPassOptions {
  bool enabled = true;
  TIntersectionOptions adjustment;  // adjustment.radius_m comes from the dataset
  // 001 §III-D fits the straight cylinders to the scene points of the first and last metre of
  // each straight section.
  double end_fit_length_m = 1.0;
  // P_r, the pose the adjustment holds, is the red section's key frame this many radii of
  // travel before its last one, and the key frames after it join the adjustment: the straight
  // windows leave the stretch before a T from which the camera sees into it turned (the last
  // key frame 4-12.6 degrees off the truth against those 0.5-2 m before it on the simulated
  // network's 400 mm pipe, where key frames mid-section differ by 0.3-5.2, median 1.4),
  // because the points they see in the T are held to the straight wall; the T's model places
  // those points on the nearer of its two walls. In radii, since how far ahead the camera sees
  // into the T scales with the pipe. 0: P_r is the section's last key frame, as in 001.
  double red_lead_radii = 2.5;
  // A straight section with less travel than this on either side leaves the T unmodelled.
  double min_end_length_m = 0.3;
  // Axes closer than this to parallel are a pass straight through, not a turn: no model.
  double min_turn_deg = 20.0;
  // The angle of the network's fittings, when the user knows it (a 90-degree tee, a 45-degree
  // wye): every T's phi is held at it (or at 180 less it, whichever is nearer the chained turn)
  // instead of measured, since the images measure a T's angle poorly (docs/fisheye_mapping.md,
  // "Turns confirmed or not"). 0: measured, the default.
  double fitting_angle_deg = 0.0;
  // The two end cylinders' axes must pass within this many radii of each other to meet in a T.
  double max_axis_gap_radii = 1.0;
  // An adjustment is applied only when it converged: image RMS and wall RMS (times the radius)
  // as for the straight windows; the end cylinders' fits (median distance) too.
  double max_rms_px = 1.5;
  double max_cylinder_rms = 0.05;
  // ... and when it moves P_b by less than this share of the chained straight-line distance
  // from P_r to P_b (the network's Ts moved it by 7-14 %; a solution that moves it by metres
  // diverged).
  double max_blue_shift = 0.5;
  double min_triangulation_angle_deg = 1.5;
  double max_start_error_px = 10.0;
  // The adjustment starts from the chained T scaled by each of these about the red section's last
  // key frame and keeps the
  // solution whose capped reprojection errors over all the T's observations are least. The
  // range leans long because of how the chain measures a T, not because of one data set: its
  // step lengths put the points it sees on the straight section's wall, but the branch's wall
  // lies farther out, so the steps come out short. (On the simulated network the chosen
  // starts were 1.2-1.4; 0.9 and 1.0 stay in case a chain comes out right or long.)
  std::vector<double> start_scales = {0.9, 1.0, 1.1, 1.2, 1.3, 1.4, 1.5};
  // ... and then, at the chosen scale, from phi turned by each of these from the chained turn,
  // keeping the least score again: an adjustment ends near the phi it starts from (the images
  // say little about a T's angle), and the chain's turn can be far off (11.6 degrees at route
  // A's T2, seed 41). Not when the fittings' angle is given. All sixteen starts of
  // the test network's one T took 106 s on this machine (docs/fisheye_mapping.md, "The T
  // pass's speed").
  std::vector<double> start_phi_offsets_deg = {-16.0, -12.0, -8.0, -4.0, 4.0, 8.0, 12.0, 16.0};
};

// One T-intersection of the route as the pass found and adjusted it.
struct TIntersectionRecord {
  int section = 0;        // the T-intersection's section
  int red_keyframe = 0;   // P_r: the red section's key frame red_lead_radii before the T
  int blue_keyframe = 0;  // P_b: the next straight section's first key frame
  // Why the T kept its chained poses (empty: adjusted): "short section", "end cylinder",
  // "no turn", "axes miss", "too few points", "not converged", "image rms", "cylinder rms",
  // "moved too far".
  std::string rejection;
  bool modelled = false;  // a model (initial or adjusted) places the centre below
  // Adjusted with phi held at the fittings' angle (fitting_angle_deg), not measured.
  bool phi_given = false;
  double model[kTIntersectionParameters] = {0, 0, 0, 0, 0};
  double initial_model[kTIntersectionParameters] = {0, 0, 0, 0, 0};  // from the end cylinders
  double axis_gap_m = 0.0;  // between the end cylinders' axes before the adjustment
  double red_fit_m = 0.0;   // median distance of the end points from their fitted wall
  double blue_fit_m = 0.0;
  int red_fit_points = 0;
  int blue_fit_points = 0;
  TIntersectionGeometry geometry;  // centre I and the axes, in the world
  double timestamp = 0.0;          // when the camera passed nearest to I
  double blue_shift_m = 0.0;       // how far the adjustment moved P_b (and all after it)
  double blue_turn_deg = 0.0;
  int triangulated_points = 0;  // the T's points at the start of the adjustment
  double start_scale = 1.0;     // the start the solution came from: the chained T's scale ...
  double start_phi_offset_deg = 0.0;  // ... and phi's turn from the chained one
  // The kept phi came from the first or last of start_phi_offsets_deg: the T's angle may lie
  // beyond the starts tried (route A's T2, seed 41, took -16 degrees), and the run says so.
  bool phi_start_at_range_end = false;
  struct StartScore {
    // "scale": the chained T scaled, on the T from the red section's last key frame when P_r
    // leads it; "phi": at the chosen scale, phi turned, on the T from P_r. Scores compare
    // within a stage only (each over its own T's observations).
    std::string stage;
    double scale = 1.0;
    double phi_offset_deg = 0.0;
    double score = 0.0;
    double phi_deg = 0.0;  // where the start's adjustment ended (its model's phi)
  };
  std::vector<StartScore> start_scores;  // every start's
  // The rigid move applied to P_b and every key frame after it (identity when not adjusted),
  // and the T's adjusted points, for the map's point cloud, with the feature track of each.
  Eigen::Isometry3d correction = Eigen::Isometry3d::Identity();
  std::vector<Eigen::Vector3d> points;
  std::vector<long> point_tracks;
  TIntersectionSummary summary;
};

// The map's points after the T of section `section` was adjusted (`t`): the T's own points
// replace the section's points and every other point of the same feature tracks (the red
// section's last stretch is seen again inside the T, and would otherwise be in the map twice,
// once from the poses before the adjustment), and the points after the T follow its correction.
std::vector<SparsePoint> MergeTIntersectionPoints(std::vector<SparsePoint> points, int section,
                                                  const TIntersectionRecord& t);

// 001 §III-D over a mapped route, after the odometry: for each T-intersection section between
// two straight sections, straight cylinders are fitted to the last metre before it (relative
// to P_r) and the first metre after it (relative to P_b), the T model is started from them,
// and the T's poses, points and model are adjusted together (OptimiseTIntersection). An
// adjusted T replaces its key frames' poses and moves P_b and every key frame after it
// rigidly to where the model puts P_b, so the two straight sections join at the T. The Ts are
// taken in the order of travel, each on the poses the earlier ones left.
class TIntersectionPass {
 public:
  TIntersectionPass(const Camera& camera, const TIntersectionPassOptions& options)
      : camera_(camera), options_(options) {}

  // `world_from_cam` per key frame and the map's `points` (each with its section) are updated
  // in place: the key frames and points after an adjusted T follow its P_b, the T's points are
  // the adjusted ones. `section_of` and `classes`: each key frame's section and each section's
  // class; `timestamps` per key frame.
  std::vector<TIntersectionRecord> Run(const KeyframeOdometry& odometry,
                                       const std::vector<int>& section_of,
                                       const std::vector<PipeViewClass>& classes,
                                       const std::vector<double>& timestamps,
                                       std::vector<Eigen::Isometry3d>* world_from_cam,
                                       std::vector<SparsePoint>* points) const;

 private:
  // The key frames' range of one T: P_r, P_b, and the end stretches fitted (001 Fig. 4a).
  struct TSpan {
    int section = 0;
    int red = 0;       // P_r, held
    int red_last = 0;  // the red section's last key frame (P_r when red_lead_radii is 0)
    int blue = 0;
    int red_start = 0;
    int blue_end = 0;
  };
  // One adjustment started from the chained T scaled by `scale` about the red section's last
  // key frame.
  // The feature tracks seen at least twice in a T's key frames, and their ids.
  struct TTracks {
    std::vector<std::vector<KeyframeOdometry::Observation>> observations;
    std::vector<long> ids;
  };
  static TTracks TracksOf(const KeyframeOdometry& odometry, int red, int blue);
  struct StartedAdjustment {
    double scale = 1.0;
    double phi_offset_deg = 0.0;
    TIntersectionProblem problem;
    std::vector<long> point_tracks;  // the feature track of each of problem.points
    TIntersectionSummary summary;
    double score = 0.0;  // squared reprojection errors capped at 3 px, over all observations
  };
  // ... with the model's phi turned by `phi_offset_deg` from the chained turn.
  StartedAdjustment AdjustFromScale(const TTracks& tracks, const TSpan& span,
                                    const std::vector<Eigen::Isometry3d>& poses,
                                    const TIntersectionProblem& cylinders, double scale,
                                    double phi_offset_deg) const;
  // The end cylinders of `span` and the model's start from them, into `problem`; false, with
  // the record's rejection, when the T cannot be modelled. Fills the record's end fits, axis
  // gap and initial model.
  bool StartModel(const TSpan& span, const std::vector<SparsePoint>& points,
                  const std::vector<Eigen::Isometry3d>& poses, TIntersectionProblem* problem,
                  TIntersectionRecord* record) const;
  // Of the starts (scale, phi offset in degrees), the one whose adjustment of `span` explains
  // the T's images best (every start's score into the record, under `stage`); nullopt when
  // none triangulated enough points.
  std::optional<StartedAdjustment> BestStart(
      const KeyframeOdometry& odometry, const TSpan& span,
      const std::vector<Eigen::Isometry3d>& poses, const TIntersectionProblem& cylinders,
      const std::vector<std::pair<double, double>>& scale_and_phi, const char* stage,
      TIntersectionRecord* record) const;
  // `span`: the T as adjusted, P_r red_lead_radii before it; `choice`: the same T with P_r its red
  // section's last key frame, on which the start is chosen.
  TIntersectionRecord AdjustOne(const KeyframeOdometry& odometry, const TSpan& span,
                                const TSpan& choice, const std::vector<double>& timestamps,
                                const std::vector<SparsePoint>& points,
                                std::vector<Eigen::Isometry3d>* world_from_cam) const;
  // Fits the straight cylinder (eq. 4) relative to key frame `origin` to the map's points of
  // `section` beside the travel from `origin` to `far`. Returns the points' median distance
  // from the wall, or a negative value with too little travel or too few points.
  double FitEndCylinder(const std::vector<SparsePoint>& points, int section, int origin, int far,
                        const std::vector<Eigen::Isometry3d>& world_from_cam, double cylinder[4],
                        int* count) const;

  const Camera& camera_;
  const TIntersectionPassOptions options_;
};

}  // namespace pipescope
