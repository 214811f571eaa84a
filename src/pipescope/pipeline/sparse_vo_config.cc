#include "pipescope/pipeline/sparse_vo_config.h"

namespace pipescope {

const OptionTable<SparseVoOptions>& SparseVoOptionTable() {
  using O = SparseVoOptions;
  static const OptionTable<O> table({
      Number<O>(
          "grid_rows", [](O& o) -> int& { return o.features.harris.grid_rows; }, 1, 100, "",
          "region Harris: rows of regions (000 §5.1)"),
      Number<O>(
          "grid_cols", [](O& o) -> int& { return o.features.harris.grid_cols; }, 1, 100, "",
          "region Harris: columns of regions"),
      Number<O>(
          "per_cell", [](O& o) -> int& { return o.features.harris.per_cell; }, 1, 10000, "",
          "region Harris: strongest corners kept per region"),
      Number<O>(
          "nms_window_px", [](O& o) -> int& { return o.features.harris.nms_window_px; }, 3, 51,
          "px", "region Harris: non-maximum suppression window"),
      Number<O>(
          "sigma_window_px", [](O& o) -> double& { return o.features.harris.sigma_window_px; }, 0.3,
          20.0, "px", "region Harris: integration scale (000: 3; 2 measured better)"),
      Number<O>(
          "sigma_derivative_px",
          [](O& o) -> double& { return o.features.harris.sigma_derivative_px; }, 0.3, 20.0, "px",
          "region Harris: derivative scale"),
      Number<O>(
          "feature_blur_sigma_px", [](O& o) -> double& { return o.features.blur_sigma_px; }, 0.0,
          20.0, "px", "Gaussian blur of the frame before detection and description, 0 = none"),
      Number<O>(
          "match_refinement_window_px",
          [](O& o) -> int& { return o.features.match_refinement_window_px; }, 0, 101, "px",
          "Lucas-Kanade window that refines each match from the key frame's patch, 0 = none"),
      Number<O>(
          "harris_k", [](O& o) -> double& { return o.features.harris.k; }, 0.0, 0.25, "",
          "region Harris: k of det - k trace^2"),
      Number<O>(
          "sift_keypoint_size_px", [](O& o) -> float& { return o.features.sift.keypoint_size_px; },
          1.0, 100.0, "px", "SIFT patch scale"),
      Number<O>(
          "max_ratio", [](O& o) -> double& { return o.features.matching.max_ratio; }, 0.1, 1.0, "",
          "descriptor matching: nearest / second-nearest distance ratio"),
      Flag<O>(
          "mutual_check", [](O& o) -> bool& { return o.features.matching.mutual_check; },
          "descriptor matching: keep mutual best matches only"),
      Number<O>(
          "ransac_threshold_px", [](O& o) -> double& { return o.features.ransac.threshold_px; },
          0.05, 50.0, "px", "five-point RANSAC inlier threshold"),
      Number<O>(
          "key_frame_min_correspondences",
          [](O& o) -> int& { return o.features.key_frames.min_correspondences; }, 6, 100000, "",
          "key frames: fewer inliers to the key frame end its span (000 §5.1)"),
      Number<O>(
          "key_frame_min_correspondence_fraction",
          [](O& o) -> double& { return o.features.key_frames.min_correspondence_fraction; }, 0.0,
          1.0, "", "key frames: ... or fewer than this share of the span's first frame's, 0 = off"),
      Number<O>(
          "key_frame_max_flow_fraction",
          [](O& o) -> double& { return o.features.key_frames.max_median_flow_fraction; }, 0.001,
          1.0, "", "key frames: a median flow above this fraction of the image ends the span"),
      Number<O>(
          "initial_key_frames", [](O& o) -> int& { return o.odometer.initial_key_frames; }, 2, 1000,
          "", "key frames of the initial-position optimisation, N_XY (000 §5.3.2)"),
      Flag<O>(
          "optimise_initial_position",
          [](O& o) -> bool& { return o.odometer.optimise_initial_position; },
          "estimate C_X, C_Y of the start by reprojection (000 §5.3.2)"),
      Flag<O>(
          "refine", [](O& o) -> bool& { return o.odometer.refine; },
          "six-degree-of-freedom refinement of the last 2N key frames (000 §5.3.3)"),
      Number<O>(
          "refine_every", [](O& o) -> int& { return o.odometer.refine_every; }, 1, 100000, "",
          "N: refine every N key frames"),
      Number<O>(
          "refine_passes", [](O& o) -> int& { return o.odometer.refine_passes; }, 1, 100, "",
          "passes over the refined key frames"),
      Number<O>(
          "refine_max_move_radii",
          [](O& o) -> double& { return o.odometer.refinement.max_position_change_radii; }, 0.0,
          10.0, "radii", "refinement: a key frame it would move further keeps its pose, 0 = any"),
      Flag<O>(
          "refine_at_end", [](O& o) -> bool& { return o.odometer.refine_at_end; },
          "refine the last window after the last key frame (beyond 000)"),
      Number<O>(
          "huber_m", [](O& o) -> double& { return o.odometer.axial_step.huber_m; }, 0.0, 1.0, "m",
          "robust loss on surface distances, 0 = off",
          [](O& o) -> double& { return o.odometer.refinement.huber_m; }),
      Number<O>(
          "reprojection_loss_px",
          [](O& o) -> double& { return o.odometer.initial_position.robust_loss_px; }, 0.0, 1000.0,
          "px", "Cauchy loss of the reprojections (000 §5.3.2 and the window adjustment), 0 = off",
          [](O& o) -> double& { return o.odometer.window.robust_loss_px; }),
      Flag<O>(
          "window_adjustment", [](O& o) -> bool& { return o.odometer.window_adjustment; },
          "joint window adjustment through the cylinder (beyond 000)"),
      Flag<O>(
          "hold_measured_start", [](O& o) -> bool& { return o.hold_measured_start; },
          "hold the first key frame's place across the pipe where the start is measured"),
      Flag<O>(
          "anchor_where_view_measures",
          [](O& o) -> bool& { return o.anchor_where_view_measures; },
          "keep the cross-section anchor where the view measures the wall distance"),
      Flag<O>(
          "pipelined", [](O& o) -> bool& { return o.pipelined; },
          "read frames and extract features on a second thread (same results)"),
      Flag<O>(
          "global_scale", [](O& o) -> bool& { return o.odometer.global_scale; },
          "one cross-section offset and travel scale over the whole run (beyond 000)"),
      Flag<O>(
          "revisit", [](O& o) -> bool& { return o.odometer.revisit; },
          "match key frames to older ones of the same place (out-and-back runs)"),
      Number<O>(
          "revisit_max_offset_fraction",
          [](O& o) -> double& { return o.odometer.revisit_max_offset_fraction; }, 0.0, 10.0, "",
          "revisits: the older key frame is within this fraction of the view's extent"),
      Number<O>(
          "revisit_min_inliers", [](O& o) -> int& { return o.odometer.revisit_min_inliers; }, 6,
          100000, "", "revisits: fewest RANSAC inliers to accept one"),
      Number<O>(
          "window_size", [](O& o) -> int& { return o.odometer.window_size; }, 2, 10000, "",
          "window adjustment: key frames adjusted"),
      Number<O>(
          "window_every", [](O& o) -> int& { return o.odometer.window_every; }, 1, 10000, "",
          "window adjustment: run every so many key frames"),
      Number<O>(
          "window_fixed", [](O& o) -> int& { return o.odometer.window_fixed; }, 0, 10000, "",
          "window adjustment: oldest key frames held"),
      Number<O>(
          "window_iterations", [](O& o) -> int& { return o.odometer.window.max_iterations; }, 1,
          1000, "", "window adjustment: Levenberg-Marquardt iterations"),
      Number<O>(
          "window_cross_section_sigma_m",
          [](O& o) -> double& { return o.odometer.window.cross_section_step_sigma_m; }, 0.0, 1.0,
          "m", "window adjustment: sigma of a key frame's step across the pipe, 0 = free"),
      Number<O>(
          "cross_section_anchor_sigma_m",
          [](O& o) -> double& { return o.odometer.window.cross_section_anchor_sigma_m; }, 0.0, 1.0,
          "m", "window adjustment: sigma holding key frames to the measured start, 0 = off"),
      Flag<O>(
          "cross_section_anchor_robust",
          [](O& o) -> bool& { return o.odometer.window.cross_section_anchor_robust; },
          "the anchor's pull fades beyond its sigma (Cauchy), so the images can overrule it"),
      Number<O>(
          "min_correspondences", [](O& o) -> int& { return o.min_correspondences; }, 6, 100000, "",
          "fewest inlier correspondences to localise a frame"),
      Number<O>(
          "restart_after_failed_frames", [](O& o) -> int& { return o.restart_after_failed_frames; },
          0, 100000, "",
          "failed frames in a row before the chain restarts at a predicted pose, 0 = never"),
      Number<O>(
          "max_cross_section_excursion",
          [](O& o) -> double& { return o.max_cross_section_excursion; }, 0.0, 1.0, "",
          "share of the radius the key frames may stray across the pipe before the run is "
          "called unreliable, 0 = no check"),
      Number<O>(
          "max_unobserved_excursion", [](O& o) -> double& { return o.max_unobserved_excursion; },
          0.0, 1.0, "",
          "where the view cannot measure the wall distance: share of it the camera may stray "
          "across the pipe before the run is called unreliable, 0 = no check"),
      Number<O>(
          "min_median_tracked", [](O& o) -> int& { return o.min_median_tracked; }, 0, 100000, "",
          "fewer tracked keypoints in the median key frame make the run unreliable, 0 = no check"),
      Choice<O>(
          "axis_along_pipe", [](O& o) -> std::string& { return o.mount.axis_along_pipe; },
          {"x", "-x", "y", "-y"}, "the camera axis that points down the pipe"),
      Number<O>(
          "wall_distance_m", [](O& o) -> double& { return o.wall_distance_m; }, 0.0, 100.0, "m",
          "start camera's distance to the wall, 0 = from the reference scale or radius"),
      Number<O>(
          "max_saturated_fraction", [](O& o) -> double& { return o.max_saturated_fraction; }, 0.0,
          1.0, "", "frames with more saturated pixels are not used"),
      Flag<O>(
          "mosaic", [](O& o) -> bool& { return o.build_mosaic; }, "write mosaic.png"),
      ScaledNumber<O>(
          "mosaic_mm_per_px", [](O& o) -> double& { return o.mosaic_pixel_m; }, 0.0, 1000.0, "mm",
          "mosaic cell, 0 = the camera's ground resolution", 0.001),
      Number<O>(
          "mosaic_spacing_cells", [](O& o) -> double& { return o.mosaic_spacing_cells; }, 0.0, 1e6,
          "cells", "frames in the mosaic are at least this far apart"),
  });
  return table;
}

}  // namespace pipescope
