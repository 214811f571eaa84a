#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>

#include "pipescope/pipeline/sparse_vo.h"

namespace pipescope {

// `--config FILE` of `pipescope odometry --method sparse`: a YAML map of the keys below (all
// optional, defaults from 000 §5). An unknown key or a bad value is an InputError naming the file
// and key.
//   grid_rows, grid_cols, per_cell, nms_window_px      region Harris (6, 8, 20, 7)
//   sigma_window_px, sigma_derivative_px, harris_k     (3.0, 1.5, 0.04)
//   sift_keypoint_size_px                              SIFT patch scale (4)
//   max_ratio, mutual_check                            matching (0.8, true)
//   ransac_threshold_px                                five-point RANSAC (1.0)
//   key_frame_min_correspondences, key_frame_max_flow_fraction   key frames (150, 0.15)
//   initial_key_frames, optimise_initial_position      §5.3.2 (10, true)
//   refine, refine_every, refine_passes, refine_at_end §5.3.3 (true, 50, 2, true)
//   window_adjustment, window_size, window_every, window_fixed, window_iterations
//                          beyond 000: joint window adjustment (true, 20, 10, 3, 15)
//   global_scale           beyond 000: one cross-section offset and scale over the run (false)
//   pipelined              read and extract features on a second thread (true)
//   huber_m                robust loss on surface distances, 0 = off (0.0005)
//   reprojection_loss_px   Cauchy loss of §5.3.2, 0 = off (1.0)
//   min_correspondences    fewest inliers to localise a frame (12)
//   axis_along_pipe        x, -x, y or -y
//   wall_distance_m        start camera's distance to the wall (0 = from the reference scale)
//   max_saturated_fraction
//   mosaic, mosaic_mm_per_px (0 = ground resolution), mosaic_spacing_cells
void ApplySparseVoConfig(const std::filesystem::path& path, SparseVoOptions* options);

// The options as run.json records them.
nlohmann::json SparseVoOptionsToJson(const SparseVoOptions& options);

}  // namespace pipescope
