#include "pipescope/pipeline/sparse_vo_config.h"

#include <set>
#include <string>

#include "pipescope/io/yaml_helpers.h"
#include "pipescope/util/error.h"

namespace pipescope {
namespace {

const std::set<std::string> kKeys = {"grid_rows",
                                     "grid_cols",
                                     "per_cell",
                                     "nms_window_px",
                                     "sigma_window_px",
                                     "sigma_derivative_px",
                                     "harris_k",
                                     "sift_keypoint_size_px",
                                     "max_ratio",
                                     "mutual_check",
                                     "hold_measured_start",
                                     "ransac_threshold_px",
                                     "key_frame_min_correspondences",
                                     "key_frame_max_flow_fraction",
                                     "initial_key_frames",
                                     "optimise_initial_position",
                                     "refine",
                                     "refine_every",
                                     "refine_passes",
                                     "refine_at_end",
                                     "huber_m",
                                     "reprojection_loss_px",
                                     "min_correspondences",
                                     "axis_along_pipe",
                                     "wall_distance_m",
                                     "max_saturated_fraction",
                                     "mosaic",
                                     "mosaic_mm_per_px",
                                     "mosaic_spacing_cells",
                                     "window_adjustment",
                                     "window_size",
                                     "window_every",
                                     "window_fixed",
                                     "window_iterations",
                                     "window_cross_section_sigma_m",
                                     "cross_section_anchor_sigma_m",
                                     "revisit",
                                     "revisit_max_offset_fraction",
                                     "revisit_min_inliers",
                                     "pipelined",
                                     "global_scale"};

class ConfigReader {
 public:
  ConfigReader(const std::filesystem::path& path, const YAML::Node& root)
      : path_(path), root_(root) {}

  template <typename T>
  void Read(const std::string& key, double low, double high, T* target) const {
    if (auto value = OptionalYamlValue<T>(root_, key, path_)) {
      if (!(static_cast<double>(*value) >= low && static_cast<double>(*value) <= high)) {
        throw InputError(path_.string() + ": key '" + key + "' must be in [" + std::to_string(low) +
                         ", " + std::to_string(high) + "], got " +
                         std::to_string(static_cast<double>(*value)));
      }
      *target = *value;
    }
  }
  void ReadBool(const std::string& key, bool* target) const {
    if (auto value = OptionalYamlValue<bool>(root_, key, path_)) *target = *value;
  }

 private:
  const std::filesystem::path& path_;
  const YAML::Node& root_;
};

}  // namespace

void ApplySparseVoConfig(const std::filesystem::path& path, SparseVoOptions* options) {
  const YAML::Node root = LoadYamlFile(path);
  RequireKnownKeys(root, path, kKeys);
  const ConfigReader r(path, root);
  r.Read("grid_rows", 1, 100, &options->harris.grid_rows);
  r.Read("grid_cols", 1, 100, &options->harris.grid_cols);
  r.Read("per_cell", 1, 10000, &options->harris.per_cell);
  r.Read("nms_window_px", 3, 51, &options->harris.nms_window_px);
  r.Read("sigma_window_px", 0.3, 20.0, &options->harris.sigma_window_px);
  r.Read("sigma_derivative_px", 0.3, 20.0, &options->harris.sigma_derivative_px);
  r.Read("harris_k", 0.0, 0.25, &options->harris.k);
  r.Read("sift_keypoint_size_px", 1.0, 100.0, &options->sift.keypoint_size_px);
  r.Read("max_ratio", 0.1, 1.0, &options->matching.max_ratio);
  r.ReadBool("mutual_check", &options->matching.mutual_check);
  r.Read("ransac_threshold_px", 0.05, 50.0, &options->ransac.threshold_px);
  r.Read("key_frame_min_correspondences", 6, 100000, &options->key_frames.min_correspondences);
  r.Read("key_frame_max_flow_fraction", 0.001, 1.0, &options->key_frames.max_median_flow_fraction);
  r.Read("initial_key_frames", 2, 1000, &options->initial_key_frames);
  r.ReadBool("optimise_initial_position", &options->optimise_initial_position);
  r.ReadBool("refine", &options->refine);
  r.Read("refine_every", 1, 100000, &options->refine_every);
  r.Read("refine_passes", 1, 100, &options->refine_passes);
  r.ReadBool("refine_at_end", &options->refine_at_end);
  double huber = options->axial_step.huber_m;
  r.Read("huber_m", 0.0, 1.0, &huber);
  options->axial_step.huber_m = huber;
  options->refinement.huber_m = huber;
  r.Read("reprojection_loss_px", 0.0, 1000.0, &options->initial_position.robust_loss_px);
  r.ReadBool("window_adjustment", &options->window_adjustment);
  r.ReadBool("hold_measured_start", &options->window.hold_first_cross_section);
  r.ReadBool("pipelined", &options->pipelined);
  r.ReadBool("global_scale", &options->global_scale);
  r.ReadBool("revisit", &options->revisit);
  r.Read("revisit_max_offset_fraction", 0.0, 10.0, &options->revisit_max_offset_fraction);
  r.Read("revisit_min_inliers", 6, 100000, &options->revisit_min_inliers);
  r.Read("window_size", 2, 10000, &options->window_size);
  r.Read("window_every", 1, 10000, &options->window_every);
  r.Read("window_fixed", 0, 10000, &options->window_fixed);
  r.Read("window_iterations", 1, 1000, &options->window.max_iterations);
  r.Read("window_cross_section_sigma_m", 0.0, 1.0, &options->window.cross_section_step_sigma_m);
  r.Read("cross_section_anchor_sigma_m", 0.0, 1.0, &options->window.cross_section_anchor_sigma_m);
  options->window.robust_loss_px = options->initial_position.robust_loss_px;
  r.Read("min_correspondences", 6, 100000, &options->min_correspondences);
  if (auto axis = OptionalYamlValue<std::string>(root, "axis_along_pipe", path)) {
    if (*axis != "x" && *axis != "-x" && *axis != "y" && *axis != "-y") {
      throw InputError(path.string() + ": key 'axis_along_pipe' must be x, -x, y or -y, got '" +
                       *axis + "'");
    }
    options->mount.axis_along_pipe = *axis;
  }
  r.Read("wall_distance_m", 0.0, 100.0, &options->wall_distance_m);
  r.Read("max_saturated_fraction", 0.0, 1.0, &options->max_saturated_fraction);
  r.ReadBool("mosaic", &options->build_mosaic);
  double mm_per_px = options->mosaic_pixel_m * 1000.0;
  r.Read("mosaic_mm_per_px", 0.0, 1000.0, &mm_per_px);
  options->mosaic_pixel_m = mm_per_px / 1000.0;
  r.Read("mosaic_spacing_cells", 0.0, 1e6, &options->mosaic_spacing_cells);
}

nlohmann::json SparseVoOptionsToJson(const SparseVoOptions& o) {
  return {{"grid_rows", o.harris.grid_rows},
          {"grid_cols", o.harris.grid_cols},
          {"per_cell", o.harris.per_cell},
          {"nms_window_px", o.harris.nms_window_px},
          {"sigma_window_px", o.harris.sigma_window_px},
          {"sigma_derivative_px", o.harris.sigma_derivative_px},
          {"harris_k", o.harris.k},
          {"sift_keypoint_size_px", o.sift.keypoint_size_px},
          {"max_ratio", o.matching.max_ratio},
          {"mutual_check", o.matching.mutual_check},
          {"ransac_threshold_px", o.ransac.threshold_px},
          {"key_frame_min_correspondences", o.key_frames.min_correspondences},
          {"key_frame_max_flow_fraction", o.key_frames.max_median_flow_fraction},
          {"initial_key_frames", o.initial_key_frames},
          {"optimise_initial_position", o.optimise_initial_position},
          {"refine", o.refine},
          {"refine_every", o.refine_every},
          {"refine_passes", o.refine_passes},
          {"refine_at_end", o.refine_at_end},
          {"huber_m", o.axial_step.huber_m},
          {"reprojection_loss_px", o.initial_position.robust_loss_px},
          {"window_adjustment", o.window_adjustment},
          {"hold_measured_start", o.window.hold_first_cross_section},
          {"pipelined", o.pipelined},
          {"global_scale", o.global_scale},
          {"revisit", o.revisit},
          {"revisit_max_offset_fraction", o.revisit_max_offset_fraction},
          {"revisit_min_inliers", o.revisit_min_inliers},
          {"window_size", o.window_size},
          {"window_every", o.window_every},
          {"window_fixed", o.window_fixed},
          {"window_iterations", o.window.max_iterations},
          {"window_cross_section_sigma_m", o.window.cross_section_step_sigma_m},
          {"cross_section_anchor_sigma_m", o.window.cross_section_anchor_sigma_m},
          {"min_correspondences", o.min_correspondences},
          {"axis_along_pipe", o.mount.axis_along_pipe},
          {"wall_distance_m", o.wall_distance_m},
          {"max_saturated_fraction", o.max_saturated_fraction},
          {"mosaic", o.build_mosaic},
          {"mosaic_mm_per_px", 1000.0 * o.mosaic_pixel_m},
          {"mosaic_spacing_cells", o.mosaic_spacing_cells}};
}

}  // namespace pipescope
