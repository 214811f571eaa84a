#include "pipescope/report/run_files.h"

#include "pipescope/util/atomic_file.h"
#include "pipescope/util/error.h"

namespace pipescope {

const Station* RunFiles::StationOfFrame(int frame) const {
  for (const Station& station : stations) {
    if (station.frame == frame) return &station;
  }
  return nullptr;
}

std::optional<std::filesystem::path> RunFiles::File(const std::string& name) const {
  const std::filesystem::path path = dir / name;
  if (std::filesystem::is_regular_file(path)) return path;
  return std::nullopt;
}

RunFiles ReadRunFiles(const std::filesystem::path& run_dir) {
  RunFiles run;
  run.dir = run_dir;
  const std::filesystem::path run_json = run_dir / "run.json";
  if (!std::filesystem::is_regular_file(run_json)) {
    throw InputError(run_dir.string() + " is not a run directory: it has no run.json");
  }
  try {
    run.run_json = nlohmann::json::parse(ReadTextFile(run_json));
  } catch (const nlohmann::json::exception& error) {
    throw InputError(run_json.string() + ": not valid JSON (" + error.what() + ")");
  }
  run.command = run.run_json.value("command", "");
  if (!run.run_json.contains("inspection") || !run.run_json.contains("inputs") ||
      !std::filesystem::is_regular_file(run_dir / "stations.csv")) {
    throw InputError(run_dir.string() +
                     " has no inspection coordinates (run.json 'inspection', stations.csv): it "
                     "was written by an older pipescope; run it again");
  }
  try {
    const nlohmann::json& inspection = run.run_json.at("inspection");
    run.station_options.line = ParseSurveyLine(inspection.at("survey_line").get<std::string>(),
                                               run_json.string() + ": inspection.survey_line");
    const std::vector<double> up = inspection.at("up").get<std::vector<double>>();
    if (up.size() != 3) throw std::invalid_argument("up");
    run.station_options.up = {up[0], up[1], up[2]};
    run.up_source = inspection.value("up_source", "");
    const nlohmann::json& radius = run.run_json.at("inputs").at("radius_m");
    run.radius_m = radius.is_null() ? 0.0 : radius.get<double>();
  } catch (const std::exception& error) {
    throw InputError(run_json.string() + ": malformed 'inspection' or 'inputs' (" + error.what() +
                     ")");
  }
  run.trajectory = ReadTumTrajectory(run_dir / "trajectory.tum");
  const std::vector<Station> rows = ReadStationsCsv(run_dir / "stations.csv");
  if (rows.size() != run.trajectory.size()) {
    throw InputError((run_dir / "stations.csv").string() + " has " + std::to_string(rows.size()) +
                     " rows, trajectory.tum " + std::to_string(run.trajectory.size()) +
                     " poses: the files are not of one run");
  }
  std::vector<int> frames;
  for (const Station& row : rows) frames.push_back(row.frame);
  run.stations = ComputeStations(run.trajectory, frames, run.station_options);
  return run;
}

}  // namespace pipescope
