#include "pipescope/pipeline/dense_vo_config.h"

#include <numbers>

namespace pipescope {

const OptionTable<DenseOdometerOptions>& DenseVoOptionTable() {
  using O = DenseOdometerOptions;
  static const OptionTable<O> table({
      Number<O>(
          "downsample", [](O& o) -> int& { return o.frames.downsample; }, 1, 16, "",
          "integer factor before registration (000: 4)"),
      Number<O>(
          "search_x_px", [](O& o) -> int& { return o.registration.full_search.max_shift_x_px; }, 1,
          100000, "px", "full-search window along image x, at the registered resolution"),
      Number<O>(
          "search_y_px", [](O& o) -> int& { return o.registration.full_search.max_shift_y_px; }, 1,
          100000, "px", "full-search window along image y"),
      Number<O>(
          "pyramid_levels", [](O& o) -> int& { return o.registration.full_search.pyramid_levels; },
          0, 6, "", "coarse-to-fine full search (0 = exhaustive, as 000)"),
      Number<O>(
          "min_correlation", [](O& o) -> double& { return o.registration.min_correlation; }, -1.0,
          1.0, "", "overlap ZNCC below which a pair counts as failed"),
      Number<O>(
          "max_saturated_fraction", [](O& o) -> double& { return o.max_saturated_fraction; }, 0.0,
          1.0, "", "frames with more saturated pixels are not registered"),
      Flag<O>(
          "phase_rotation", [](O& o) -> bool& { return o.registration.phase.estimate_rotation; },
          "phase: search the rotation too (003 eq. 7)"),
      ScaledNumber<O>(
          "max_rotation_deg", [](O& o) -> double& { return o.registration.phase.max_rotation_rad; },
          0.5, 45.0, "deg", "phase: the rotation search's range", std::numbers::pi / 180.0),
      Choice<O>(
          "axis_along_pipe", [](O& o) -> std::string& { return o.mount.axis_along_pipe; },
          {"x", "-x", "y", "-y"}, "the camera axis that points down the pipe"),
      Number<O>(
          "registration_band", [](O& o) -> double& { return o.registration_band; }, 0.05, 1.0, "",
          "planar methods: fraction of the frame across the pipe registered"),
      Flag<O>(
          "foreshortening_correction", [](O& o) -> bool& { return o.foreshortening_correction; },
          "planar methods: equalise the band's lines' axial rate (needs the radius)"),
      Custom<O>(
          "key_frame_shift_fraction", "[0, 0.45]", "",
          "key frames renewed at this fraction of the frame (0 = frame to frame); default by "
          "method: 0.4 integer searches, 0.1 sub-pixel methods",
          [](const YAML::Node& node, const std::string& where, O* o) {
            const double value = ReadOptionValue<double>(node, where);
            RequireOptionRange(value, 0.0, 0.45, where);
            o->key_frame_shift_fraction = value;
          },
          [](const O& o) {
            return nlohmann::json(
                o.key_frame_shift_fraction.value_or(KeyFrameShiftFraction(o.method)));
          }),
      Number<O>(
          "key_frame_max_rounding_px", [](O& o) -> double& { return o.key_frame_max_rounding_px; },
          0.0, 0.5, "px", "integer searches: rounding left (carried) at a key frame"),
      Number<O>(
          "key_frame_wait_fraction", [](O& o) -> double& { return o.key_frame_wait_fraction; }, 0.0,
          0.2, "", "how much further a key frame may wait for its rounding or fraction"),
      Number<O>(
          "key_frame_fraction_tolerance_px",
          [](O& o) -> double& { return o.key_frame_fraction_tolerance_px; }, 0.0, 0.5, "px",
          "Gauss-Newton methods: key frames' spread fractions (0 off)"),
      Number<O>(
          "key_frame_max_failures", [](O& o) -> int& { return o.key_frame_max_failures; }, 1, 1000,
          "", "failed frames in a row before the predicted one becomes the key"),
      Number<O>(
          "max_departure_from_prediction_px",
          [](O& o) -> double& { return o.max_departure_from_prediction_px; }, 0.0, 1e4, "px",
          "a shift this far from the constant-velocity prediction fails (0 off)"),
      Number<O>(
          "presmooth_sigma_px", [](O& o) -> double& { return o.presmooth_sigma_px; }, 0.0, 10.0,
          "px", "Gauss-Newton methods: Gaussian smoothing before registration"),
      Number<O>(
          "contrast_normalisation_px", [](O& o) -> double& { return o.contrast_normalisation_px; },
          0.0, 50.0, "px", "Gauss-Newton methods: local contrast normalisation's sigma (0 off)"),
      Custom<O>(
          "unrolled_registration", "phase | hybrid", "",
          "dense-unrolled: how the unrolled frames are registered",
          [](const YAML::Node& node, const std::string& where, O* o) {
            const std::string value = ReadOptionValue<std::string>(node, where);
            if (value != "phase" && value != "hybrid") {
              throw InputError(where + " must be phase or hybrid, got '" + value + "'");
            }
            o->unrolled_registration =
                value == "phase" ? DenseMethod::kPhase : DenseMethod::kHybrid;
          },
          [](const O& o) {
            return nlohmann::json(o.unrolled_registration == DenseMethod::kPhase ? "phase"
                                                                                 : "hybrid");
          }),
      Choice<O>(
          "measure_cross_section", [](O& o) -> std::string& { return o.measure_cross_section; },
          {"auto", "on", "off"},
          "dense-unrolled: measure the crawler's place across the pipe at each key frame "
          "(auto: where the view sees the wall's curvature)"),
      Number<O>(
          "cross_section_stride_px", [](O& o) -> int& { return o.cross_section.stride_px; }, 1,
          64, "px", "measure_cross_section: every n-th prepared pixel of the key frame aligned"),
      ScaledNumber<O>(
          "cross_section_step_sigma_mm",
          [](O& o) -> double& { return o.cross_section.offset_step_sigma_m; }, 0.0, 100.0, "mm",
          "measure_cross_section: how far the crawler's place may move per key frame (1 sigma; 0: "
          "no prior)",
          0.001),
      Number<O>(
          "cross_section_baseline_fraction",
          [](O& o) -> double& { return o.cross_section_baseline_fraction; }, 0.0, 0.9, "",
          "measure_cross_section: a key frame is aligned with one this share of the grid behind"),
      Number<O>(
          "cross_section_faint_smooth_px",
          [](O& o) -> double& { return o.cross_section_faint_smooth_px; }, 0.0, 10.0, "px",
          "measure_cross_section: on a wall too faint to align, align frames blurred by this "
          "(0: hold the place instead)"),
      Number<O>(
          "cross_section_huber_sigmas", [](O& o) -> double& { return o.cross_section.huber_sigmas; },
          0.1, 100.0, "", "measure_cross_section: Huber's loss beyond this many residual sigmas"),
      Flag<O>(
          "mosaic", [](O& o) -> bool& { return o.build_mosaic; }, "write mosaic.png"),
      Number<O>(
          "mosaic_spacing_px", [](O& o) -> double& { return o.mosaic_spacing_px; }, 0.0, 1e6, "px",
          "frames used in the mosaic are at least this far apart"),
      Custom<O>(
          "max_speed_m_s", "[1e-06, 100] or null", "m/s",
          "bounds the full-search window by the speed and the frame rate (000 Algorithm 1)",
          [](const YAML::Node& node, const std::string& where, O* o) {
            const double value = ReadOptionValue<double>(node, where);
            RequireOptionRange(value, 1e-6, 100.0, where);
            o->max_speed_m_s = value;
          },
          [](const O& o) {
            return o.max_speed_m_s ? nlohmann::json(*o.max_speed_m_s) : nlohmann::json(nullptr);
          }),
  });
  return table;
}

}  // namespace pipescope
