#include "pipescope/pipeline/ekf_vo_config.h"

namespace pipescope {

const OptionTable<EkfVoOptions>& EkfVoOptionTable() {
  using O = EkfVoOptions;
  static const OptionTable<O> table({
      Number<O>(
          "max_features", [](O& o) -> int& { return o.tracker.max_features; }, 8, 100000, "",
          "tracking: features kept per frame"),
      Number<O>(
          "grid_cols", [](O& o) -> int& { return o.tracker.grid_cols; }, 1, 100, "",
          "tracking: columns of the grid the features are spread over"),
      Number<O>(
          "grid_rows", [](O& o) -> int& { return o.tracker.grid_rows; }, 1, 100, "",
          "tracking: rows of that grid"),
      Number<O>(
          "quality_level", [](O& o) -> double& { return o.tracker.quality_level; }, 1e-6, 1.0, "",
          "tracking: corner strength relative to the cell's strongest"),
      Number<O>(
          "min_distance_px", [](O& o) -> double& { return o.tracker.min_distance_px; }, 1.0, 1000.0,
          "px", "tracking: spacing of features"),
      Number<O>(
          "klt_window_px", [](O& o) -> int& { return o.tracker.window_px; }, 5, 101, "px",
          "tracking: Lucas-Kanade window"),
      Number<O>(
          "pyramid_levels", [](O& o) -> int& { return o.tracker.pyramid_levels; }, 0, 8, "",
          "tracking: Lucas-Kanade pyramid levels above the image"),
      Number<O>(
          "max_round_trip_px", [](O& o) -> double& { return o.tracker.max_round_trip_px; }, 0.01,
          100.0, "px", "tracking: forward-backward check"),
      Number<O>(
          "view_margin_windows", [](O& o) -> double& { return o.tracker.view_margin_windows; }, 0.0,
          20.0, "windows",
          "tracking: no feature within this many Lucas-Kanade windows of the lit view's edge (a "
          "fisheye's image circle)"),
      Number<O>(
          "min_grey", [](O& o) -> double& { return o.tracker.min_grey; }, 0.0, 255.0, "grey",
          "tracking: no new features on pixels darker than this"),
      Number<O>(
          "flat_field_width_share", [](O& o) -> double& { return o.flat_field_width_share; }, -1.0,
          1.0, "",
          "tracking: Lucas-Kanade tracks the frame over its blur of this sigma (share of the "
          "width; 0 = the frame; -1 = 0.1 rad at the image centre looking down the tube, 0 at "
          "the wall)"),
      Number<O>(
          "linear_acceleration_sigma",
          [](O& o) -> double& { return o.filter.linear_acceleration_sigma; }, 1e-6, 1000.0, "m/s^2",
          "filter: linear acceleration noise (004 eq. 6)"),
      Number<O>(
          "angular_acceleration_sigma",
          [](O& o) -> double& { return o.filter.angular_acceleration_sigma; }, 1e-6, 1000.0,
          "rad/s^2", "filter: angular acceleration noise (004 eq. 6)"),
      Number<O>(
          "pixel_sigma", [](O& o) -> double& { return o.filter.pixel_sigma; }, 0.01, 100.0, "px",
          "filter: localisation noise of a feature"),
      Number<O>(
          "gate_chi2", [](O& o) -> double& { return o.filter.gate_chi2; }, 0.1, 1e6, "",
          "filter: Mahalanobis gate of a feature's innovation (2 dof)"),
      Number<O>(
          "iterations", [](O& o) -> int& { return o.filter.iterations; }, 1, 20, "",
          "filter: iterations of the update (1 = plain EKF)"),
      Number<O>(
          "min_features", [](O& o) -> int& { return o.filter.min_features; }, 3, 100000, "",
          "filter: fewest features an update needs"),
      Number<O>(
          "max_range_radii", [](O& o) -> double& { return o.filter.max_range_radii; }, 0.1, 1000.0,
          "radii", "filter: features farther along the tube are not used"),
      Number<O>(
          "far_feature_radii", [](O& o) -> double& { return o.filter.far_feature_radii; }, 0.0,
          1000.0, "radii",
          "filter: a feature's pixel sigma grows with the square of its range past this (0 = no)"),
      Number<O>(
          "initial_speed_sigma", [](O& o) -> double& { return o.filter.initial_speed_sigma; }, 1e-6,
          100.0, "m/s", "filter: initial uncertainty of the speed"),
      Number<O>(
          "initial_angular_speed_sigma",
          [](O& o) -> double& { return o.filter.initial_angular_speed_sigma; }, 1e-6, 100.0,
          "rad/s", "filter: initial uncertainty of the angular speed"),
      Number<O>(
          "initial_axis_sigma_rad", [](O& o) -> double& { return o.filter.initial_axis_sigma_rad; },
          1e-6, 3.0, "rad", "filter: initial uncertainty of the first section's axis"),
      Number<O>(
          "initial_offset_sigma_radii",
          [](O& o) -> double& { return o.filter.initial_offset_sigma_radii; }, 1e-6, 1.0, "radii",
          "filter: initial uncertainty of the camera's place across the first section"),
      Number<O>(
          "radius_prior_sigma", [](O& o) -> double& { return o.filter.radius_prior_sigma; }, 0.0,
          1.0, "", "filter: relative sigma of the dataset's radius on the first section"),
      Number<O>(
          "spawn_gated_fraction", [](O& o) -> double& { return o.filter.spawn_gated_fraction; },
          0.0, 1.0, "", "sections: share of gated features that counts a frame as unexplained"),
      Number<O>(
          "spawn_track_drift_px", [](O& o) -> double& { return o.filter.spawn_track_drift_px; },
          0.0, 1e6, "px",
          "sections: median drift of tracks from their wall points that counts a "
          "frame as unexplained"),
      Number<O>(
          "track_min_age_frames", [](O& o) -> int& { return o.filter.track_min_age_frames; }, 1,
          100000, "", "sections: youngest track whose drift is measured"),
      Number<O>(
          "track_max_age_frames", [](O& o) -> int& { return o.filter.track_max_age_frames; }, 1,
          100000, "", "sections: oldest track whose drift is measured"),
      Number<O>(
          "spawn_frames", [](O& o) -> int& { return o.filter.spawn_frames; }, 1, 100000, "",
          "sections: unexplained frames in a row that start a new section"),
      Number<O>(
          "min_section_length_radii",
          [](O& o) -> double& { return o.filter.min_section_length_radii; }, 0.0, 1000.0, "radii",
          "sections: shortest section"),
      Number<O>(
          "spawn_lookahead_radii", [](O& o) -> double& { return o.spawn_lookahead_radii; }, -1.0,
          100.0, "radii",
          "sections: a new section starts at least this far ahead of the camera (-1: 1 looking "
          "down the tube, 2 for a wall-looking camera)"),
      Flag<O>(
          "extrapolate_turn", [](O& o) -> bool& { return o.filter.extrapolate_turn; },
          "sections: a new section first continues the turn between the last two"),
      Number<O>(
          "new_section_offset_sigma_radii",
          [](O& o) -> double& { return o.filter.new_section_offset_sigma_radii; }, 1e-6, 1.0,
          "radii", "sections: initial uncertainty of a new section's start across its axis"),
      Number<O>(
          "new_section_axis_sigma_rad",
          [](O& o) -> double& { return o.filter.new_section_axis_sigma_rad; }, 1e-6, 3.0, "rad",
          "sections: initial uncertainty of a new section's axis"),
      Number<O>(
          "new_section_radius_sigma",
          [](O& o) -> double& { return o.filter.new_section_radius_sigma; }, 1e-6, 1.0, "",
          "sections: relative sigma of a new section's radius about the dataset's"),
      Number<O>(
          "curvature_sigma_radii", [](O& o) -> double& { return o.curvature_sigma_radii; }, -1.0,
          2.0, "1/radii",
          "sections: prior sigma of a section's curvature times the radius (a section may bend as "
          "a torus segment; 0: straight sections only, as 004; -1: 0.3 looking down the tube, 0 "
          "for a wall-looking camera)"),
      Number<O>(
          "max_active_sections", [](O& o) -> int& { return o.filter.max_active_sections; }, 1, 100,
          "", "sections: kept in the filter's state; older ones are frozen"),
      Choice<O>(
          "axis_along_tube", [](O& o) -> std::string& { return o.axis_along_tube; },
          {"auto", "z", "x", "y"},
          "the camera axis along the tube at the start (z: looking down it; auto: the measured "
          "direction of travel)"),
      Flag<O>(
          "metric", [](O& o) -> bool& { return o.metric; },
          "the dataset's radius makes the run metric (false: up to scale)"),
      Flag<O>(
          "mosaic", [](O& o) -> bool& { return o.build_mosaic; }, "write mosaic.png (dewarped)"),
      ScaledNumber<O>(
          "mosaic_mm_per_px", [](O& o) -> double& { return o.mosaic.pixel_m; }, 0.0, 1000.0, "mm",
          "mosaic cell, 0 = a hundredth of the radius", 0.001),
      Number<O>(
          "mosaic_frame_spacing_radii",
          [](O& o) -> double& { return o.mosaic_frame_spacing_radii; }, 0.0, 100.0, "radii",
          "mosaic: frames painted are at least this far apart"),
      Number<O>(
          "max_saturated_fraction", [](O& o) -> double& { return o.max_saturated_fraction; }, 0.0,
          1.0, "", "frames with more saturated pixels are not used"),
  });
  return table;
}

}  // namespace pipescope
