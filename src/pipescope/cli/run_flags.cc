#include "pipescope/cli/run_flags.h"

#include <cstdio>

#include "pipescope/cli/flag_checks.h"
#include "pipescope/util/error.h"
#include "pipescope/util/output_paths.h"

namespace pipescope {

void AddRunFlags(CLI::App* command, RunFlags* flags, const std::string& config_help) {
  command->add_option("dataset", flags->dataset, "Dataset folder, manifest, or image folder");
  command->add_option("--out", flags->out, "Run directory to write");
  command->add_option("--config", flags->config, config_help);
  command->add_option("--camera", flags->camera, "Calibration, for a plain image folder");
  command->add_option("--radius", flags->radius, "Pipe inner radius in metres")
      ->check(FiniteRange(kMinPipeRadiusM, kMaxPipeRadiusM));
  command->add_option("--fps", flags->fps, "Frame rate of a plain image folder (default 30)")
      ->check(FinitePositive(1e5));
  command->add_flag("--no-report", flags->no_report,
                    "Do not write report.html (pipescope report RUN writes it later)");
  command->add_flag("--list-keys", flags->list_keys,
                    "Print every --config key with its default, range and help");
}

DatasetManifest OpenRunDataset(const RunFlags& flags) {
  if (flags.dataset.empty()) throw InputError("the dataset (first argument) is required");
  if (flags.out.empty()) throw InputError("flag --out is required");
  DatasetManifest manifest =
      OpenDataset(flags.dataset,
                  {.camera_path = flags.camera, .inner_radius_m = flags.radius, .fps = flags.fps});
  std::vector<NamedInput> inputs = DatasetInputs(flags.dataset, manifest);
  inputs.push_back({flags.config, "--config"});
  RefuseOutputOverInputs(flags.out, "--out", inputs);
  return manifest;
}

void RequireCameraView(const Camera& camera, const std::filesystem::path& camera_path,
                       double min_deg, double max_deg, const std::string& requirement) {
  const double half_angle_deg = ImageHalfAngleDeg(camera);
  if (half_angle_deg < min_deg || half_angle_deg > max_deg) {
    char range[96];
    std::snprintf(range, sizeof(range), " degrees off its axis (this method: %.0f to %.0f); ",
                  min_deg, max_deg);
    throw InputError(camera_path.string() + ": the camera sees " +
                     std::to_string(static_cast<int>(half_angle_deg)) + range + requirement);
  }
}

}  // namespace pipescope
