#include "pipescope/cli/run_flags.h"

#include "pipescope/util/error.h"

namespace pipescope {

void AddRunFlags(CLI::App* command, RunFlags* flags, const std::string& config_help) {
  command->add_option("dataset", flags->dataset, "Dataset folder, manifest, or image folder");
  command->add_option("--out", flags->out, "Run directory to write");
  command->add_option("--config", flags->config, config_help);
  command->add_option("--camera", flags->camera, "Calibration, for a plain image folder");
  command->add_option("--radius", flags->radius, "Pipe inner radius in metres")
      ->check(CLI::PositiveNumber);
  command->add_flag("--list-keys", flags->list_keys,
                    "Print every --config key with its default, range and help");
}

DatasetManifest OpenRunDataset(const RunFlags& flags) {
  if (flags.dataset.empty()) throw InputError("the dataset (first argument) is required");
  if (flags.out.empty()) throw InputError("flag --out is required");
  return OpenDataset(flags.dataset,
                     {.camera_path = flags.camera, .inner_radius_m = flags.radius, .fps = {}});
}

}  // namespace pipescope
