#include "pipescope/pipeline/dense_vo_config.h"

#include <cmath>
#include <numbers>
#include <set>
#include <string>

#include "pipescope/io/yaml_helpers.h"
#include "pipescope/util/error.h"

namespace pipescope {
namespace {

const std::set<std::string> kKeys = {"downsample",
                                     "search_x_px",
                                     "search_y_px",
                                     "max_speed_m_s",
                                     "pyramid_levels",
                                     "min_correlation",
                                     "max_saturated_fraction",
                                     "phase_rotation",
                                     "max_rotation_deg",
                                     "axis_along_pipe",
                                     "mosaic",
                                     "mosaic_spacing_px",
                                     "registration_band",
                                     "foreshortening_correction",
                                     "key_frame_shift_fraction",
                                     "key_frame_max_rounding_px",
                                     "key_frame_wait_fraction",
                                     "key_frame_max_failures",
                                     "key_frame_fraction_tolerance_px",
                                     "max_departure_from_prediction_px",
                                     "presmooth_sigma_px",
                                     "contrast_normalisation_px",
                                     "unrolled_registration"};

void RequireRange(const std::filesystem::path& file, const std::string& key, double value,
                  double low, double high) {
  if (!(value >= low && value <= high)) {
    throw InputError(file.string() + ": key '" + key + "' must be in [" + std::to_string(low) +
                     ", " + std::to_string(high) + "], got " + std::to_string(value));
  }
}

}  // namespace

void ApplyDenseVoConfig(const std::filesystem::path& path, DenseVoOptions* options) {
  const YAML::Node root = LoadYamlFile(path);
  RequireKnownKeys(root, path, kKeys);
  if (auto value = OptionalYamlValue<int>(root, "downsample", path)) {
    RequireRange(path, "downsample", *value, 1, 16);
    options->frames.downsample = *value;
  }
  FullSearchOptions& search = options->registration.full_search;
  if (auto value = OptionalYamlValue<int>(root, "search_x_px", path)) {
    RequireRange(path, "search_x_px", *value, 1, 100000);
    search.max_shift_x_px = *value;
  }
  if (auto value = OptionalYamlValue<int>(root, "search_y_px", path)) {
    RequireRange(path, "search_y_px", *value, 1, 100000);
    search.max_shift_y_px = *value;
  }
  if (auto value = OptionalYamlValue<int>(root, "pyramid_levels", path)) {
    RequireRange(path, "pyramid_levels", *value, 0, 6);
    search.pyramid_levels = *value;
  }
  if (auto value = OptionalYamlValue<double>(root, "min_correlation", path)) {
    RequireRange(path, "min_correlation", *value, -1.0, 1.0);
    options->registration.min_correlation = *value;
  }
  if (auto value = OptionalYamlValue<double>(root, "max_saturated_fraction", path)) {
    RequireRange(path, "max_saturated_fraction", *value, 0.0, 1.0);
    options->max_saturated_fraction = *value;
  }
  if (auto value = OptionalYamlValue<bool>(root, "phase_rotation", path)) {
    options->registration.phase.estimate_rotation = *value;
  }
  if (auto value = OptionalYamlValue<double>(root, "max_rotation_deg", path)) {
    RequireRange(path, "max_rotation_deg", *value, 0.5, 45.0);
    options->registration.phase.max_rotation_rad = *value * std::numbers::pi / 180.0;
  }
  if (auto value = OptionalYamlValue<std::string>(root, "axis_along_pipe", path)) {
    if (*value != "x" && *value != "-x" && *value != "y" && *value != "-y") {
      throw InputError(path.string() + ": key 'axis_along_pipe' must be x, -x, y or -y, got '" +
                       *value + "'");
    }
    options->mount.axis_along_pipe = *value;
  }
  if (auto value = OptionalYamlValue<double>(root, "registration_band", path)) {
    RequireRange(path, "registration_band", *value, 0.05, 1.0);
    options->registration_band = *value;
  }
  if (auto value = OptionalYamlValue<double>(root, "key_frame_shift_fraction", path)) {
    RequireRange(path, "key_frame_shift_fraction", *value, 0.0, 0.45);
    options->key_frame_shift_fraction = *value;
  }
  if (auto value = OptionalYamlValue<double>(root, "key_frame_max_rounding_px", path)) {
    RequireRange(path, "key_frame_max_rounding_px", *value, 0.0, 0.5);
    options->key_frame_max_rounding_px = *value;
  }
  if (auto value = OptionalYamlValue<double>(root, "key_frame_wait_fraction", path)) {
    RequireRange(path, "key_frame_wait_fraction", *value, 0.0, 0.2);
    options->key_frame_wait_fraction = *value;
  }
  if (auto value = OptionalYamlValue<double>(root, "key_frame_fraction_tolerance_px", path)) {
    RequireRange(path, "key_frame_fraction_tolerance_px", *value, 0.0, 0.5);
    options->key_frame_fraction_tolerance_px = *value;
  }
  if (auto value = OptionalYamlValue<int>(root, "key_frame_max_failures", path)) {
    RequireRange(path, "key_frame_max_failures", *value, 1, 1000);
    options->key_frame_max_failures = *value;
  }
  if (auto value = OptionalYamlValue<double>(root, "max_departure_from_prediction_px", path)) {
    RequireRange(path, "max_departure_from_prediction_px", *value, 0.0, 1e4);
    options->max_departure_from_prediction_px = *value;
  }
  if (auto value = OptionalYamlValue<bool>(root, "foreshortening_correction", path)) {
    options->foreshortening_correction = *value;
  }
  if (auto value = OptionalYamlValue<double>(root, "presmooth_sigma_px", path)) {
    RequireRange(path, "presmooth_sigma_px", *value, 0.0, 10.0);
    options->presmooth_sigma_px = *value;
  }
  if (auto value = OptionalYamlValue<double>(root, "contrast_normalisation_px", path)) {
    RequireRange(path, "contrast_normalisation_px", *value, 0.0, 50.0);
    options->contrast_normalisation_px = *value;
  }
  if (auto value = OptionalYamlValue<std::string>(root, "unrolled_registration", path)) {
    if (*value != "phase" && *value != "hybrid") {
      throw InputError(path.string() +
                       ": key 'unrolled_registration' must be phase or hybrid, got '" + *value +
                       "'");
    }
    options->unrolled_registration = *value == "phase" ? DenseMethod::kPhase : DenseMethod::kHybrid;
  }
  if (auto value = OptionalYamlValue<bool>(root, "mosaic", path)) options->build_mosaic = *value;
  if (auto value = OptionalYamlValue<double>(root, "mosaic_spacing_px", path)) {
    RequireRange(path, "mosaic_spacing_px", *value, 0.0, 1e6);
    options->mosaic_spacing_px = *value;
  }
  if (auto value = OptionalYamlValue<double>(root, "max_speed_m_s", path)) {
    RequireRange(path, "max_speed_m_s", *value, 1e-6, 100.0);
    options->max_speed_m_s = *value;
  }
}

nlohmann::json DenseVoOptionsToJson(const DenseVoOptions& options) {
  const FullSearchOptions& search = options.registration.full_search;
  return {
      {"method", DenseMethodName(options.method)},
      {"downsample", options.frames.downsample},
      {"search_x_px", search.max_shift_x_px},
      {"search_y_px", search.max_shift_y_px},
      {"pyramid_levels", search.pyramid_levels},
      {"min_correlation", options.registration.min_correlation},
      {"max_saturated_fraction", options.max_saturated_fraction},
      {"phase_rotation", options.registration.phase.estimate_rotation},
      {"max_rotation_deg", options.registration.phase.max_rotation_rad * 180.0 / std::numbers::pi},
      {"axis_along_pipe", options.mount.axis_along_pipe},
      {"registration_band", options.registration_band},
      {"foreshortening_correction", options.foreshortening_correction},
      {"key_frame_shift_fraction",
       options.key_frame_shift_fraction.value_or(KeyFrameShiftFraction(options.method))},
      {"key_frame_max_rounding_px", options.key_frame_max_rounding_px},
      {"key_frame_wait_fraction", options.key_frame_wait_fraction},
      {"key_frame_fraction_tolerance_px", options.key_frame_fraction_tolerance_px},
      {"key_frame_max_failures", options.key_frame_max_failures},
      {"max_departure_from_prediction_px", options.max_departure_from_prediction_px},
      {"presmooth_sigma_px", options.presmooth_sigma_px},
      {"contrast_normalisation_px", options.contrast_normalisation_px},
      {"unrolled_registration",
       options.unrolled_registration == DenseMethod::kPhase ? "phase" : "hybrid"},
      {"mosaic", options.build_mosaic},
      {"mosaic_spacing_px", options.mosaic_spacing_px},
      {"max_speed_m_s",
       options.max_speed_m_s ? nlohmann::json(*options.max_speed_m_s) : nlohmann::json(nullptr)},
  };
}

}  // namespace pipescope
