// `pipescope simulate`: renders a pipe dataset with exact ground truth (GUIDE §4-5).
#include <spdlog/spdlog.h>

#include <cmath>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "pipescope/cli/flag_checks.h"
#include "pipescope/cli/subcommand.h"
#include "pipescope/synthetic/dataset_writer.h"
#include "pipescope/synthetic/presets.h"
#include "pipescope/util/error.h"

namespace pipescope {
namespace {

// A dataset whose frames stop more than this short of its route's end is said to (metres).
constexpr double kRouteLeftToleranceM = 0.05;

struct SimulateFlags {
  std::string preset;
  std::string out;
  int frames = 0;
  long long seed = -1;
  std::vector<std::string> assignments;
  bool list_presets = false;
};

void ListPresets() {
  std::cout << "Presets:\n";
  for (const std::string& name : PresetNames()) {
    std::cout << "  " << name << "\n      " << PresetConfig(name).description << "\n";
  }
  std::cout << "\nKeys for --set key=value (defaults per preset):\n";
  std::printf("  %-26s", "key");
  for (const std::string& name : PresetNames()) std::printf(" %-19s", name.c_str());
  std::printf("\n");
  for (const ConfigKey& key : SimulationConfigKeys()) {
    std::printf("  %-26s", key.name);
    for (const std::string& name : PresetNames()) {
      std::printf(" %-19s", GetConfigValue(PresetConfig(name), key.name).c_str());
    }
    std::printf("\n      %s\n", key.help);
  }
}

int RunSimulate(const SimulateFlags& flags) {
  if (flags.list_presets) {
    ListPresets();
    return kExitSuccess;
  }
  if (flags.preset.empty()) throw InputError("flag --preset is required (see --list-presets)");
  if (flags.out.empty()) throw InputError("flag --out is required");
  const SimulationConfig preset = PresetConfig(flags.preset);
  SimulationConfig config = preset;
  for (const std::string& assignment : flags.assignments) SetConfigValue(&config, assignment);
  if (flags.frames > 0) config.frames = flags.frames;
  if (flags.seed >= 0) config.seed = static_cast<std::uint64_t>(flags.seed);
  spdlog::info("simulating {} ({} frames, {}x{}, {}) into {}", config.preset, config.frames,
               config.width, config.height, config.camera_model, flags.out);
  const SimulationSummary summary = SimulateDataset(config, flags.out);
  spdlog::info("wrote {}: {} frames in {:.1f} s ({:.1f} frames/s)", flags.out, summary.frames,
               summary.seconds, summary.frames / summary.seconds);
  if (summary.route_length_m > 0) {
    spdlog::info("the camera travels {:.3f} m (the route is {:.2f} m long)", summary.travelled_m,
                 summary.route_length_m);
  }
  // A preset's frame count was chosen for its own route (001 dataset A: 26 000 frames); another
  // route (route=B) may need more, and a dataset that then stops short of the route's end (route B
  // before its second pass of T1-T4, the one loop closure needs) must say so. Presets whose frames
  // stop before their travel's end by design (culvert, tube-bend) and counts the user chose are
  // only logged.
  if (summary.route_left_m > kRouteLeftToleranceM && summary.route_driven_m > 0.0) {
    const bool other_route = config.route != preset.route && config.frames == preset.frames;
    const int enough = static_cast<int>(
        std::ceil(1.02 * config.frames * (summary.route_driven_m + summary.route_left_m) /
                  summary.route_driven_m / 500.0) *
        500.0);
    const std::string message = fmt::format(
        "the {} frames end {:.2f} m before the end of the route ({:.2f} of {:.2f} m driven); "
        "about --frames {} would drive all of it",
        config.frames, summary.route_left_m, summary.route_driven_m,
        summary.route_driven_m + summary.route_left_m, enough);
    if (other_route) {
      spdlog::warn("{}", message);
    } else {
      spdlog::info("{}", message);
    }
  }
  return kExitSuccess;
}

}  // namespace

SubcommandRunner SetupSimulateCommand(CLI::App* command) {
  auto flags = std::make_shared<SimulateFlags>();
  command->add_option("--preset", flags->preset, "Preset to render (see --list-presets)");
  command->add_option("--out", flags->out, "Dataset folder to write");
  command->add_option("--frames", flags->frames, "Render only the first N frames")
      ->check(FiniteRange(1, 1e8));
  command->add_option("--seed", flags->seed, "Seed for texture, motion and noise")
      ->check(FiniteRange(0, 4294967295.0));
  command->add_option("--set", flags->assignments, "Override a preset key: key=value")
      ->allow_extra_args(false);
  command->add_flag("--list-presets", flags->list_presets,
                    "Print the presets and every settable key with its default");
  return [flags] { return RunSimulate(*flags); };
}

}  // namespace pipescope
