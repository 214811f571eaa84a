#include "pipescope/pipeline/fisheye_mapping_config.h"

namespace pipescope {

const OptionTable<FisheyeMappingOptions>& FisheyeMappingOptionTable() {
  using O = FisheyeMappingOptions;
  static const OptionTable<O> table({
      // Tracking and classification (001 §III-A, §III-B).
      Choice<O>(
          "matcher", [](O& o) -> std::string& { return o.tracking.matcher; },
          {kTemplateMatcher, kLucasKanadeMatcher},
          "how frames find the key frame's features: templates (001) or lucas-kanade (followed "
          "frame to frame; for weak texture under noise)"),
      Number<O>(
          "lk_window_px", [](O& o) -> int& { return o.tracking.lk_window_px; }, 5, 101, "px",
          "lucas-kanade: window side"),
      Number<O>(
          "lk_max_round_trip_px", [](O& o) -> double& { return o.tracking.lk_max_round_trip_px; },
          0.01, 100.0, "px", "lucas-kanade: a track must return within this when tracked back"),
      Number<O>(
          "lk_flat_field_sigma_px",
          [](O& o) -> double& { return o.tracking.lk_flat_field_sigma_px; }, 0.0, 1000.0, "px",
          "lucas-kanade: the frames are divided by their blur of this sigma (0: the frames as "
          "they are)"),
      Number<O>(
          "lk_features_per_region", [](O& o) -> int& { return o.tracking.lk_features_per_region; },
          1, 10000, "", "lucas-kanade: corners a region holds at a key frame, followed ones first"),
      Number<O>(
          "per_region", [](O& o) -> int& { return o.tracking.harris.per_cell; }, 1, 10000, "",
          "region Harris: strongest corners per region (001: 200; matcher: templates)"),
      Number<O>(
          "min_median_flow_px", [](O& o) -> double& { return o.tracking.min_median_flow_px; }, 0.1,
          1000.0, "px", "a key frame when the median flow to the last one reaches this"),
      Number<O>(
          "max_median_flow_px", [](O& o) -> double& { return o.tracking.max_median_flow_px; }, 0.1,
          1000.0, "px",
          "... or when the next frame's would pass this at the recent pace (every frame a key "
          "frame for a fast crawler)"),
      Number<O>(
          "min_correspondence_fraction",
          [](O& o) -> double& { return o.tracking.min_correspondence_fraction; }, 0.0, 1.0, "",
          "... or the inliers fall below this share of the first frame's after the key frame"),
      Number<O>(
          "min_similarity", [](O& o) -> double& { return o.tracking.matching.min_similarity; },
          -1.0, 1.0, "", "template matching (matcher: templates): cosine similarity of a match"),
      Number<O>(
          "inlier_threshold_rad",
          [](O& o) -> double& { return o.tracking.relative_pose.inlier_threshold_rad; }, 1e-5, 0.5,
          "rad", "relative pose on the sphere: RANSAC inlier threshold"),
      Flag<O>(
          "guided_matching", [](O& o) -> bool& { return o.tracking.guided_matching; },
          "epipolar-guided ZNCC matching in the fisheye image (matcher: templates)"),
      Number<O>(
          "min_zncc", [](O& o) -> double& { return o.tracking.guided.min_zncc; }, -1.0, 1.0, "",
          "guided matching (matcher: templates): ZNCC of a match"),
      Number<O>(
          "max_view_angle_deg", [](O& o) -> double& { return o.tracking.max_view_angle_deg; }, 1.0,
          180.0, "deg", "features further from the optical axis are not tracked"),
      Number<O>(
          "far_wall_corners", [](O& o) -> int& { return o.tracking.far_wall_corners; }, 0, 10000,
          "", "corners added within far_wall_cone_deg of the optical axis (0: none)"),
      Number<O>(
          "far_wall_cone_deg", [](O& o) -> double& { return o.tracking.far_wall_cone_deg; }, 1.0,
          90.0, "deg", "the cone of the far-wall corners"),
      Number<O>(
          "max_straight_moment_ratio",
          [](O& o) -> double& { return o.classification.max_straight_moment_ratio; }, 1.0, 100.0,
          "", "straight / T classification: L_p / L of a straight view (001 §III-B)"),
      Number<O>(
          "dark_fraction_of_median",
          [](O& o) -> double& { return o.classification.dark_fraction_of_median; }, 0.0, 1.0, "",
          "classification: a pixel darker than this fraction of the median is dark"),
      Number<O>(
          "min_cluster_size", [](O& o) -> int& { return o.min_cluster_size; }, 1, 100000, "",
          "key frames: the classes' temporal filter (001 Fig. 3d)"),
      // The odometry and its windows (001 §III-C).
      Number<O>(
          "window_interval", [](O& o) -> int& { return o.odometry.window_interval; }, 1, 100000, "",
          "adjust a window every so many key frames (001: 50)"),
      Number<O>(
          "window_size", [](O& o) -> int& { return o.odometry.window_size; }, 3, 100000, "",
          "key frames in a window (001: 100)"),
      Number<O>(
          "min_window_keyframes", [](O& o) -> int& { return o.odometry.min_window_keyframes; }, 3,
          100000, "", "a shorter window (a short section, or just after a reset) is not run"),
      Number<O>(
          "tau", [](O& o) -> double& { return o.odometry.window.tau; }, 0.0, 1e12, "",
          "weight of the cylinder term (001 eq. 2: 2.5e5)"),
      Flag<O>(
          "use_cylinder", [](O& o) -> bool& { return o.odometry.window.use_cylinder; },
          "the cylinder term in straight sections"),
      Number<O>(
          "huber_px", [](O& o) -> double& { return o.odometry.window.huber_px; }, 0.01, 1000.0,
          "px", "Huber threshold of the image term"),
      Number<O>(
          "mad_factor", [](O& o) -> double& { return o.odometry.window.mad_factor; }, 0.5, 100.0,
          "", "MAD outlier removal: factor of 1.4826 MAD"),
      Number<O>(
          "stages", [](O& o) -> int& { return o.odometry.window.stages; }, 1, 100, "",
          "outlier-removal stages of a window"),
      Number<O>(
          "max_iterations_per_stage",
          [](O& o) -> int& { return o.odometry.window.max_iterations_per_stage; }, 1, 10000, "",
          "Levenberg-Marquardt iterations of the last stage"),
      Number<O>(
          "max_iterations_before_outlier_removal",
          [](O& o) -> int& { return o.odometry.window.max_iterations_before_outlier_removal; }, 1,
          10000, "", "Levenberg-Marquardt iterations of the earlier stages"),
      Number<O>(
          "axis_prior_sigma_deg",
          [](O& o) -> double& { return o.odometry.window.axis_prior_sigma_deg; }, 1e-6, 180.0,
          "deg", "axis prior: sigma of the angle to the previous window's axis"),
      Number<O>(
          "axis_prior_sigma_m",
          [](O& o) -> double& { return o.odometry.window.axis_prior_sigma_m; }, 1e-9, 10.0, "m",
          "axis prior: sigma of the axes' offset"),
      Number<O>(
          "first_rotation_sigma_deg",
          [](O& o) -> double& { return o.odometry.window.first_rotation_sigma_deg; }, 1e-6, 180.0,
          "deg", "sigma of the window's first rotation when the axis prior holds it"),
      Number<O>(
          "window_threads", [](O& o) -> int& { return o.odometry.window.num_threads; }, 1, 64, "",
          "threads of a window's solve"),
      Number<O>(
          "min_triangulation_angle_deg",
          [](O& o) -> double& { return o.odometry.min_triangulation_angle_deg; }, 0.0, 90.0, "deg",
          "a new point needs this angle between its first and latest rays"),
      Number<O>(
          "min_scale_parallax_rad",
          [](O& o) -> double& { return o.odometry.min_scale_parallax_rad; }, 0.0, 1.5, "rad",
          "a point fixes the step's scale only when its two rays part by this"),
      Number<O>(
          "min_cylinder_scale_points",
          [](O& o) -> int& { return o.odometry.min_cylinder_scale_points; }, 1, 100000, "",
          "fewest two-view points to take the step length from the radius"),
      Flag<O>(
          "fit_axis_per_step", [](O& o) -> bool& { return o.odometry.fit_axis_per_step; },
          "fit the axis with the scale to each step's points"),
      Number<O>(
          "stale_axis_keyframes", [](O& o) -> int& { return o.odometry.stale_axis_keyframes; }, 1,
          100000, "", "without a window for this long, the axis is fitted per step"),
      Flag<O>(
          "refine_pose_on_structure",
          [](O& o) -> bool& { return o.odometry.refine_pose_on_structure; },
          "refine each step on the triangulated points"),
      Number<O>(
          "max_step_direction_change_deg",
          [](O& o) -> double& { return o.odometry.max_step_direction_change_deg; }, 0.0, 90.0,
          "deg", "a translation further off the recent direction is rejected"),
      Number<O>(
          "stationary_parallax_rad",
          [](O& o) -> double& { return o.odometry.stationary_parallax_rad; }, 0.0, 0.5, "rad",
          "a key-frame step with less median parallax stood still"),
      Number<O>(
          "max_step_change", [](O& o) -> double& { return o.odometry.max_step_change; }, 1.0, 100.0,
          "", "a step length more than this factor off the recent speed is not taken"),
      Number<O>(
          "speed_history", [](O& o) -> int& { return o.odometry.speed_history; }, 1, 10000, "",
          "key-frame steps of the recent speed"),
      Flag<O>(
          "retriangulate_in_window",
          [](O& o) -> bool& { return o.odometry.retriangulate_in_window; },
          "triangulate every track of a window anew from its poses"),
      Number<O>(
          "max_window_start_error_px",
          [](O& o) -> double& { return o.odometry.max_window_start_error_px; }, 0.0, 1e6, "px",
          "observations further off start a window as outliers"),
      Flag<O>(
          "axis_prior", [](O& o) -> bool& { return o.odometry.axis_prior; },
          "tie each straight window's cylinder to the previous window's axis"),
      Number<O>(
          "max_window_length_change",
          [](O& o) -> double& { return o.odometry.max_window_length_change; }, 1.0, 100.0, "",
          "a window whose path length changes by more than this factor is dropped"),
      Number<O>(
          "max_window_speed_ratio",
          [](O& o) -> double& { return o.odometry.max_window_speed_ratio; }, 1.0, 1000.0, "",
          "... or whose fastest step is more than this factor over its median speed"),
      Number<O>(
          "max_window_rms_px", [](O& o) -> double& { return o.odometry.max_window_rms_px; }, 0.0,
          1000.0, "px", "a window is applied only below this image RMS"),
      Number<O>(
          "max_window_cylinder_rms",
          [](O& o) -> double& { return o.odometry.max_window_cylinder_rms; }, 0.0, 10.0, "radii",
          "... and with its points on the wall to this RMS"),
      Number<O>(
          "max_rejected_window_share", [](O& o) -> double& { return o.max_rejected_window_share; },
          0.0, 1.0, "", "a run is unreliable when more of its straight windows were rejected"),
      Number<O>(
          "max_rejected_section_window_share",
          [](O& o) -> double& { return o.max_rejected_section_window_share; }, 0.0, 1.0, "",
          "... or more of one straight section's windows (a section with 4 or more)"),
      Flag<O>(
          "overlap_odometry", [](O& o) -> bool& { return o.overlap_odometry; },
          "run the odometry on a second thread while tracking (same results)"),
      // T-intersections (001 §III-D).
      Flag<O>(
          "t_model", [](O& o) -> bool& { return o.t_intersections.enabled; },
          "adjust each T-intersection with the two-cylinder model and join its sections"),
      Number<O>(
          "t_end_fit_length_m", [](O& o) -> double& { return o.t_intersections.end_fit_length_m; },
          0.05, 100.0, "m", "T model: the straight cylinders fit this much travel on each side"),
      Number<O>(
          "t_red_lead_radii", [](O& o) -> double& { return o.t_intersections.red_lead_radii; }, 0.0,
          100.0, "radii",
          "T model: the pose held is this much travel before the T (0: the last before it)"),
      Number<O>(
          "t_min_turn_deg", [](O& o) -> double& { return o.t_intersections.min_turn_deg; }, 5.0,
          89.0, "deg", "T model: axes closer to parallel are a pass straight through"),
      Number<O>(
          "t_fitting_angle_deg",
          [](O& o) -> double& { return o.t_intersections.fitting_angle_deg; }, 0.0, 179.0, "deg",
          "T model: the fittings' angle, held instead of measured (0: measured)"),
      Number<O>(
          "t_max_axis_gap_radii",
          [](O& o) -> double& { return o.t_intersections.max_axis_gap_radii; }, 0.0, 100.0, "radii",
          "T model: the end cylinders' axes must pass this close to meet"),
      // Loop closure (001 §III-E).
      Flag<O>(
          "loop_closure", [](O& o) -> bool& { return o.loop_closure.enabled; },
          "close loops where the plan (scene.yaml with route_start) says a section was driven "
          "twice"),
      Number<O>(
          "loop_pairs", [](O& o) -> int& { return o.loop_closure.max_pairs; }, 1, 1000, "",
          "loop closure: at most this many key frame pairs per two passes of a section"),
      Number<O>(
          "loop_search_step_m", [](O& o) -> double& { return o.loop_closure.search_step_m; }, 0.005,
          100.0, "m",
          "loop closure: the later pass's key frames tried against each candidate, this far apart"),
      Number<O>(
          "loop_max_runner_up_share",
          [](O& o) -> double& { return o.loop_closure.max_runner_up_share; }, 0.0, 1.0, "",
          "loop closure: a candidate is refused when another place "
          "(loop_ambiguity_separation_radii away) matches with this share of its best place's "
          "inliers (1: never)"),
      Number<O>(
          "loop_ambiguity_separation_radii",
          [](O& o) -> double& { return o.loop_closure.ambiguity_separation_radii; }, 0.0, 1000.0,
          "radii", "loop closure: how far along the later pass another place must lie"),
      Number<O>(
          "loop_step_translation_sigma_m",
          [](O& o) -> double& { return o.loop_closure.step_translation_sigma_m; }, 1e-6, 1.0, "m",
          "loop closure: how far a key-frame step may move, on each axis (in a T too)"),
      Number<O>(
          "loop_step_rotation_sigma_deg",
          [](O& o) -> double& { return o.loop_closure.step_rotation_sigma_deg; }, 1e-4, 180.0,
          "deg", "loop closure: how far a straight section's key-frame step may turn"),
      Number<O>(
          "loop_t_step_rotation_sigma_deg",
          [](O& o) -> double& { return o.loop_closure.t_step_rotation_sigma_deg; }, 0.001, 180.0,
          "deg", "loop closure: how far a step inside a T may turn (its own turn's edge aside)"),
      Number<O>(
          "loop_t_turn_sigma_deg",
          [](O& o) -> double& { return o.loop_closure.t_turn_sigma_deg; }, 0.0, 1000.0, "deg",
          "loop closure: standard deviation of each T's turn, P_r to P_b, as one edge (0: no "
          "such edge)"),
      Number<O>(
          "loop_t_turn_huber_sigmas",
          [](O& o) -> double& { return o.loop_closure.t_turn_huber_sigmas; }, 0.0, 1000.0, "",
          "loop closure: a T's turn costs linearly beyond this many sigmas (0: squared)"),
      // The dense appearance map (001 §IV-B).
      Flag<O>(
          "dense_map", [](O& o) -> bool& { return o.dense_map.enabled; },
          "write points_dense.ply and a mosaic per straight section"),
      Number<O>(
          "dense_spacing_m", [](O& o) -> double& { return o.dense_map.appearance.spacing_m; },
          0.0005, 0.1, "m", "dense map: distance between points on the wall"),
      Flag<O>(
          "dense_taper", [](O& o) -> bool& { return o.dense_map.appearance.colatitude_taper; },
          "dense map: views weighted by a sine over the colatitude band (false: 001's mean)"),
      Number<O>(
          "dense_piece_length_m", [](O& o) -> double& { return o.dense_map.piece_length_m; }, 0.05,
          100.0, "m", "dense map: travel mapped on one fitted cylinder"),
      Number<O>(
          "dense_keyframe_spacing_m",
          [](O& o) -> double& { return o.dense_map.keyframe_spacing_m; }, 0.0, 10.0, "m",
          "dense map: key frames closer than this along the path are skipped"),
  });
  return table;
}

}  // namespace pipescope
