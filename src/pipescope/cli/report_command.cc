// `pipescope report RUN`: writes (or rewrites) report.html of a run directory (docs/formats.md).
#include <spdlog/spdlog.h>

#include <iostream>
#include <memory>
#include <string>

#include "pipescope/cli/subcommand.h"
#include "pipescope/report/report_page.h"
#include "pipescope/util/error.h"
#include "pipescope/util/output_paths.h"

namespace pipescope {
namespace {

struct ReportFlags {
  std::string run;
  std::string dataset;
  std::string out;
};

// The files of a run the report reads: none may be where the report goes.
std::vector<NamedInput> RunInputs(const std::filesystem::path& run) {
  std::vector<NamedInput> inputs;
  for (const char* name : {"run.json", "trajectory.tum", "stations.csv", "metrics.json",
                           "mosaic.png", "classification.png", "points_sparse.ply", "keyframes.tum",
                           "junctions.yaml", "observations_located.csv", "camera.yaml"}) {
    inputs.push_back({run / name, "the run's " + std::string(name)});
  }
  return inputs;
}

int RunReportCommand(const ReportFlags& flags) {
  const std::filesystem::path out = flags.out.empty()
                                        ? std::filesystem::path(flags.run) / "report.html"
                                        : std::filesystem::path(flags.out);
  std::vector<NamedInput> inputs = RunInputs(flags.run);
  if (!flags.dataset.empty()) inputs.push_back({flags.dataset, "--dataset"});
  RefuseOutputOverInputs(out, "--out", inputs);
  if (std::filesystem::is_directory(out)) {
    throw InputError("--out " + out.string() + " is a folder; give the report's file name");
  }
  WriteReportPage(flags.run, out, {.dataset = flags.dataset});
  spdlog::info("wrote {}", out.string());
  std::cout << std::filesystem::absolute(out).string() << "\n";
  return kExitSuccess;
}

}  // namespace

SubcommandRunner SetupReportCommand(CLI::App* command) {
  auto flags = std::make_shared<ReportFlags>();
  command->add_option("run", flags->run, "Run directory of odometry or map")
      ->required()
      ->check(CLI::ExistingDirectory);
  command
      ->add_option("--dataset", flags->dataset,
                   "Dataset to take the ground truth and frames from (default: the run's)")
      ->check(CLI::ExistingPath);
  command->add_option("--out", flags->out, "The report's file (default RUN/report.html)");
  return [flags] { return RunReportCommand(*flags); };
}

}  // namespace pipescope
