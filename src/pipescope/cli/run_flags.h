#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>

#include "pipescope/io/dataset.h"

namespace pipescope {

// The flags every command that writes a run directory takes (`odometry`, `map`).
struct RunFlags {
  std::string dataset;
  std::string out;
  std::string config;
  std::string camera;
  std::optional<double> radius;
  bool list_keys = false;
};

// Adds the run flags to `command`; `config_help` describes --config.
void AddRunFlags(CLI::App* command, RunFlags* flags, const std::string& config_help);

// The dataset of a run: InputError naming the dataset argument or --out when either is missing
// (neither is required by the parser, so that --list-keys works alone).
DatasetManifest OpenRunDataset(const RunFlags& flags);

}  // namespace pipescope
