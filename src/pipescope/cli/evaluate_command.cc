// `pipescope evaluate`: metrics.json (GUIDE §4) from a ground-truth and an estimated trajectory.
#include <spdlog/spdlog.h>

#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "pipescope/cli/flag_checks.h"
#include "pipescope/cli/subcommand.h"
#include "pipescope/eval/dense_map_evaluation.h"
#include "pipescope/eval/junction_metrics.h"
#include "pipescope/eval/metrics_report.h"
#include "pipescope/eval/trajectory_metrics.h"
#include "pipescope/io/junctions.h"
#include "pipescope/io/trajectory.h"
#include "pipescope/synthetic/simulation_yaml.h"
#include "pipescope/util/atomic_file.h"
#include "pipescope/util/error.h"
#include "pipescope/util/output_paths.h"

namespace pipescope {
namespace {

struct EvaluateFlags {
  std::string groundtruth;
  std::string estimate;
  std::string scene;
  std::string junctions;
  std::string dense_map;
  std::string simulation;
  std::string alignment = "se3";
  std::string json;
  double max_dt_s = 0.01;
};

int RunEvaluate(const EvaluateFlags& flags) {
  if (flags.scene.empty() != flags.junctions.empty()) {
    throw InputError("flags --scene and --junctions go together: give both or neither");
  }
  if (flags.dense_map.empty() != flags.simulation.empty()) {
    throw InputError("flags --dense-map and --simulation go together: give both or neither");
  }
  RefuseOutputOverInputs(flags.json, "--json",
                         {{flags.groundtruth, "--gt"},
                          {flags.estimate, "--est"},
                          {flags.scene, "--scene"},
                          {flags.junctions, "--junctions"},
                          {flags.simulation, "--simulation"}});
  if (!flags.dense_map.empty()) {
    const std::filesystem::path run = flags.dense_map;
    RefuseOutputOverInputs(flags.json, "--json",
                           {{run / "run.json", "--dense-map's run.json"},
                            {run / "keyframes.tum", "--dense-map's keyframes.tum"}});
  }
  EvaluationOptions options;
  options.alignment = AlignmentFromName(flags.alignment);
  options.max_dt_s = flags.max_dt_s;
  const Trajectory ground_truth = ReadTumTrajectory(flags.groundtruth);
  const Trajectory estimate = ReadTumTrajectory(flags.estimate);
  Metrics metrics;
  try {
    metrics = EvaluateTrajectory(ground_truth, estimate, options);
  } catch (const InputError& error) {
    throw InputError("--gt " + flags.groundtruth + " and --est " + flags.estimate + ": " +
                     error.what());
  }
  if (!flags.scene.empty()) {
    metrics.junction_distances = EvaluateJunctionDistances(
        ground_truth, ReadSceneJunctions(flags.scene), ReadEstimatedJunctions(flags.junctions));
  }
  if (!flags.dense_map.empty()) {
    const Simulation simulation(ReadSimulationConfig(flags.simulation));
    metrics.dense_map =
        EvaluateDenseMap(flags.dense_map, ground_truth, simulation, flags.max_dt_s);
  }
  std::cout << MetricsToTable(metrics);
  if (!flags.json.empty()) {
    WriteTextFileAtomically(flags.json, MetricsToJson(metrics).dump(2) + "\n");
    spdlog::info("wrote {}", flags.json);
  }
  return kExitSuccess;
}

}  // namespace

SubcommandRunner SetupEvaluateCommand(CLI::App* command) {
  auto flags = std::make_shared<EvaluateFlags>();
  command->add_option("--gt", flags->groundtruth, "Ground-truth trajectory (TUM)")
      ->required()
      ->check(CLI::ExistingFile);
  command->add_option("--est", flags->estimate, "Estimated trajectory (TUM)")
      ->required()
      ->check(CLI::ExistingFile);
  command->add_option("--scene", flags->scene, "scene.yaml with the true junction centres")
      ->check(CLI::ExistingFile);
  command->add_option("--junctions", flags->junctions, "junctions.yaml of the run")
      ->check(CLI::ExistingFile);
  command
      ->add_option("--dense-map", flags->dense_map,
                   "A map run folder: score its dense map against the simulated albedo")
      ->check(CLI::ExistingDirectory);
  command
      ->add_option("--simulation", flags->simulation,
                   "simulation.yaml of the simulated dataset the run mapped (with --dense-map)")
      ->check(CLI::ExistingFile);
  command->add_option("--align", flags->alignment, "Alignment before ATE")
      ->check(CLI::IsMember({"se3", "sim3", "none"}))
      ->capture_default_str();
  command->add_option("--max-dt", flags->max_dt_s, "Timestamp association tolerance, seconds")
      ->check(FinitePositive(3600.0))
      ->capture_default_str();
  command->add_option("--json", flags->json, "Write the metrics as JSON to this file");
  return [flags] { return RunEvaluate(*flags); };
}

}  // namespace pipescope
