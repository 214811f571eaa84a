#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>

#include "pipescope/camera/camera.h"
#include "pipescope/io/dataset.h"

namespace pipescope {

// The flags every command that writes a run directory takes (`odometry`, `map`).
struct RunFlags {
  std::string dataset;
  std::string out;
  std::string config;
  std::string camera;
  std::optional<double> radius;
  std::optional<double> fps;
  bool list_keys = false;
  bool no_report = false;
};

// Adds the run flags to `command`; `config_help` describes --config.
void AddRunFlags(CLI::App* command, RunFlags* flags, const std::string& config_help);

// The dataset of a run: InputError naming the dataset argument or --out when either is missing
// (neither is required by the parser, so that --list-keys works alone).
DatasetManifest OpenRunDataset(const RunFlags& flags);

// InputError naming `camera_path` unless the camera sees between `min_deg` and `max_deg` off its
// axis at the image border (ImageHalfAngleDeg): a method given a set-up it cannot measure.
// `requirement` says what the method needs and what to use instead.
void RequireCameraView(const Camera& camera, const std::filesystem::path& camera_path,
                       double min_deg, double max_deg, const std::string& requirement);

}  // namespace pipescope
