// `pipescope demo`: the main job on a built-in default (GUIDE §5). Simulates 8 s of the 16-inch
// steel pipe, runs dense odometry on the unrolled wall, places three example observations and
// prints where report.html is.
#include <spdlog/spdlog.h>

#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "pipescope/camera/camera_io.h"
#include "pipescope/cli/subcommand.h"
#include "pipescope/util/atomic_file.h"
#include "pipescope/util/error.h"

namespace pipescope {
namespace {

struct DemoFlags {
  std::string out = "demo_out";
  int frames = 240;
};

// Three observations an inspector might record, in frames spread over the run: points at the
// image centre and a box around it (the camera looks at the wall, so each meets it).
std::string DemoObservations(const Camera& camera, int frames) {
  const double u = 0.5 * (camera.Width() - 1), v = 0.5 * (camera.Height() - 1);
  const double du = 0.15 * camera.Width(), dv = 0.15 * camera.Height();
  std::string csv = "frame,u_min,v_min,u_max,v_max,code,remark\n";
  csv += std::to_string(frames / 6) + "," + std::to_string(u) + "," + std::to_string(v) + "," +
         std::to_string(u) + "," + std::to_string(v) + ",MWL,example point at the image centre\n";
  csv += std::to_string(frames / 2) + "," + std::to_string(u - du) + "," + std::to_string(v - dv) +
         "," + std::to_string(u + du) + "," + std::to_string(v + dv) +
         ",CM,\"example box, 30 % of the image\"\n";
  csv += std::to_string(5 * frames / 6) + "," + std::to_string(u) + "," + std::to_string(v - dv) +
         "," + std::to_string(u) + "," + std::to_string(v - dv) +
         ",TF,example point above the centre\n";
  return csv;
}

int RunDemo(const DemoFlags& flags) {
  const std::filesystem::path out = flags.out;
  const std::string dataset = (out / "steel-16in").string();
  const std::string run = (out / "run").string();
  std::filesystem::create_directories(out);
  for (const std::vector<std::string>& step :
       {std::vector<std::string>{"pipescope", "simulate", "--preset", "steel-16in", "--frames",
                                 std::to_string(flags.frames), "--out", dataset},
        std::vector<std::string>{"pipescope", "odometry", dataset, "--method", "dense-unrolled",
                                 "--out", run, "--no-report"}}) {
    spdlog::info("demo: pipescope {} ...", step[1]);
    if (const int status = RunCommandLine(step); status != kExitSuccess) return status;
  }
  const std::filesystem::path observations = out / "observations.csv";
  WriteTextFileAtomically(observations,
                          DemoObservations(ReadCamera(out / "run" / "camera.yaml"), flags.frames));
  const std::vector<std::vector<std::string>> finish = {
      {"pipescope", "locate", run, "--observations", observations.string()},
      {"pipescope", "report", run}};
  for (const std::vector<std::string>& step : finish) {
    if (const int status = RunCommandLine(step); status != kExitSuccess) return status;
  }
  const std::filesystem::path report = std::filesystem::absolute(out / "run" / "report.html");
  std::cout << "\nDemo done.\n"
            << "  dataset:  " << std::filesystem::absolute(dataset).string()
            << " (images/, groundtruth.tum, dataset.yaml)\n"
            << "  run:      " << std::filesystem::absolute(run).string()
            << " (trajectory.tum, stations.csv, mosaic.png, run.json, metrics.json, "
               "observations_located.csv)\n"
            << "  report:   " << report.string() << "\n"
            << "Open the report in a browser: file://" << report.string() << "\n";
  return kExitSuccess;
}

}  // namespace

SubcommandRunner SetupDemoCommand(CLI::App* command) {
  auto flags = std::make_shared<DemoFlags>();
  command->add_option("--out", flags->out, "Folder for the demo's dataset and run")
      ->capture_default_str();
  command->add_option("--frames", flags->frames, "Frames to simulate")
      ->check(CLI::Range(30, 3000))
      ->capture_default_str();
  return [flags] { return RunDemo(*flags); };
}

}  // namespace pipescope
