// `pipescope locate RUN`: where a pixel of a frame, or each observation of a list, lies on the
// pipe wall: distance along the pipe and clock position (GUIDE §4 inspection coordinates).
#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "pipescope/camera/camera_io.h"
#include "pipescope/cli/subcommand.h"
#include "pipescope/report/observation_locator.h"
#include "pipescope/report/report_page.h"
#include "pipescope/util/atomic_file.h"
#include "pipescope/util/error.h"
#include "pipescope/util/output_paths.h"

namespace pipescope {
namespace {

struct LocateFlags {
  std::string run;
  std::optional<int> frame;
  std::string pixel;
  std::string json;
  std::string observations;
  std::string out;
};

Eigen::Vector2d ParsePixel(const std::string& text) {
  double u = 0.0, v = 0.0;
  char end = 0;
  if (std::sscanf(text.c_str(), "%lf,%lf%c", &u, &v, &end) != 2 || !std::isfinite(u) ||
      !std::isfinite(v)) {
    throw InputError("--pixel: expected U,V (two numbers, e.g. 320,240), not '" + text + "'");
  }
  return {u, v};
}

int LocateOnePixel(const LocateFlags& flags, const RunFiles& run, const Camera& camera) {
  if (!flags.frame || flags.pixel.empty()) {
    throw InputError("give --frame N and --pixel U,V, or --observations FILE");
  }
  Observation observation;
  observation.frame = *flags.frame;
  const Eigen::Vector2d pixel = ParsePixel(flags.pixel);
  observation.u_min = observation.u_max = pixel.x();
  observation.v_min = observation.v_max = pixel.y();
  if (!camera.IsInImage(pixel)) {
    throw InputError("--pixel " + flags.pixel + " lies outside the " +
                     std::to_string(camera.Width()) + "x" + std::to_string(camera.Height()) +
                     " image");
  }
  const LocatedObservation located = LocateObservation(run, camera, observation);
  if (!located.located)
    throw InputError("--frame " + std::to_string(*flags.frame) + ": " + located.why_not);
  const WallLocation& at = located.centre;
  const bool clocked = std::isfinite(at.clock_angle_deg);
  std::printf("frame %d pixel (%.1f, %.1f): distance %.4f m, clock %s (%.1f deg), section %d\n",
              observation.frame, pixel.x(), pixel.y(), at.distance_m,
              clocked ? at.clock.c_str() : "undefined", at.clock_angle_deg, at.section);
  if (!flags.json.empty()) {
    const nlohmann::json json = {
        {"frame", observation.frame},
        {"pixel", {pixel.x(), pixel.y()}},
        {"distance_m", at.distance_m},
        {"clock", clocked ? nlohmann::json(at.clock) : nlohmann::json(nullptr)},
        {"clock_angle_deg", clocked ? nlohmann::json(at.clock_angle_deg) : nlohmann::json(nullptr)},
        {"section", at.section},
        {"point_m", {at.point.x(), at.point.y(), at.point.z()}}};
    WriteTextFileAtomically(flags.json, json.dump(2) + "\n");
  }
  return kExitSuccess;
}

int LocateObservations(const LocateFlags& flags, const RunFiles& run, const Camera& camera) {
  const std::filesystem::path out =
      flags.out.empty() ? std::filesystem::path(flags.run) / "observations_located.csv"
                        : std::filesystem::path(flags.out);
  std::vector<LocatedObservation> located;
  int placed = 0;
  for (const Observation& observation : ReadObservationsCsv(flags.observations)) {
    located.push_back(LocateObservation(run, camera, observation));
    if (located.back().located) {
      ++placed;
    } else {
      spdlog::warn("{}: the observation in frame {} is not placed: {}", flags.observations,
                   observation.frame, located.back().why_not);
    }
  }
  WriteLocatedObservationsCsv(out, located);
  spdlog::info("placed {} of {} observations; wrote {}", placed, located.size(), out.string());
  // The run's report lists the observations: bring it up to date.
  const std::filesystem::path report = std::filesystem::path(flags.run) / "report.html";
  if (out == std::filesystem::path(flags.run) / "observations_located.csv" &&
      std::filesystem::is_regular_file(report)) {
    WriteReportPage(flags.run, report, {});
    spdlog::info("updated {}", report.string());
  }
  return kExitSuccess;
}

int RunLocate(const LocateFlags& flags) {
  const bool many = !flags.observations.empty();
  if (many && (flags.frame || !flags.pixel.empty())) {
    throw InputError("give either --frame and --pixel, or --observations, not both");
  }
  const std::filesystem::path run_dir = flags.run;
  std::vector<NamedInput> inputs = {{run_dir / "run.json", "the run's run.json"},
                                    {run_dir / "trajectory.tum", "the run's trajectory.tum"},
                                    {run_dir / "stations.csv", "the run's stations.csv"},
                                    {run_dir / "camera.yaml", "the run's camera.yaml"},
                                    {flags.observations, "--observations"}};
  if (!flags.json.empty()) RefuseOutputOverInputs(flags.json, "--json", inputs);
  if (!flags.out.empty()) RefuseOutputOverInputs(flags.out, "--out", inputs);
  const RunFiles run = ReadRunFiles(run_dir);
  const Camera camera = ReadCamera(run_dir / "camera.yaml");
  return many ? LocateObservations(flags, run, camera) : LocateOnePixel(flags, run, camera);
}

}  // namespace

SubcommandRunner SetupLocateCommand(CLI::App* command) {
  auto flags = std::make_shared<LocateFlags>();
  command->add_option("run", flags->run, "Run directory of odometry")
      ->required()
      ->check(CLI::ExistingDirectory);
  command->add_option("--frame", flags->frame, "Frame number (0 = the dataset's first)")
      ->check(CLI::NonNegativeNumber);
  command->add_option("--pixel", flags->pixel, "Pixel U,V of the frame (0,0 = top-left pixel)");
  command->add_option("--json", flags->json, "Also write the location as JSON to this file");
  command
      ->add_option("--observations", flags->observations,
                   "CSV of observations: frame, u, v (or u_min, v_min, u_max, v_max), code, "
                   "remark")
      ->check(CLI::ExistingFile);
  command->add_option("--out", flags->out,
                      "Where --observations writes (default RUN/observations_located.csv)");
  return [flags] { return RunLocate(*flags); };
}

}  // namespace pipescope
