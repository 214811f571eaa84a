#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>

#include "pipescope/pipeline/dense_vo.h"

namespace pipescope {

// `--config FILE` of `pipescope odometry` for the dense methods: a YAML map of the keys below
// (all optional). An unknown key or a bad value is an InputError naming the file and key.
//   downsample             integer factor before registration (000: 4)
//   search_x_px, search_y_px   full-search window at the registered resolution
//   max_speed_m_s          bounds the window instead (000 Algorithm 1), with the frame rate
//   pyramid_levels         coarse-to-fine full search (0 = exhaustive, as 000)
//   min_correlation        overlap ZNCC below which a pair counts as failed
//   max_saturated_fraction frames with more saturated pixels are not registered
//   phase_rotation         phase: search the rotation too (003 eq. 7); default false
//   max_rotation_deg       phase: the rotation search's range
//   registration_band      planar methods: fraction of the frame across the pipe registered
//   presmooth_sigma_px     Gauss-Newton methods: Gaussian smoothing before registration
//   contrast_normalisation_px  Gauss-Newton methods: local contrast normalisation's sigma (0 off)
//   key_frame_shift_fraction   key frames renewed at this fraction of the frame (0 = frame to
//   frame) key_frame_max_rounding_px  integer searches: rounding left (carried) at a key frame
//   key_frame_wait_fraction    how much further a key frame may wait for its rounding or fraction
//   key_frame_fraction_tolerance_px  Gauss-Newton methods: key frames' spread fractions (0 off)
//   key_frame_max_failures     failed frames in a row before the predicted one becomes the key
//   max_departure_from_prediction_px  a shift this far from the prediction fails (0 off)
//   foreshortening_correction  planar methods: equalise the band's lines' axial rate
//   unrolled_registration      dense-unrolled: phase or hybrid
//   axis_along_pipe        x, -x, y or -y: the camera axis pointing down the pipe
//   mosaic                 write mosaic.png
//   mosaic_spacing_px      frames used in the mosaic are at least this far apart
void ApplyDenseVoConfig(const std::filesystem::path& path, DenseVoOptions* options);

// The options as run.json records them.
nlohmann::json DenseVoOptionsToJson(const DenseVoOptions& options);

}  // namespace pipescope
