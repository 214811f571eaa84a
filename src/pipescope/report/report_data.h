#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>

namespace pipescope {

struct ReportOptions {
  // A dataset to read the ground truth and frames from instead of the one run.json names
  // (`report --dataset`): for a run whose dataset has moved.
  std::filesystem::path dataset;
  // The run directory as the report names it, when the files are read from elsewhere (a run
  // writes its report in its staging folder before putting it in place); empty: the one read.
  std::filesystem::path shown_directory;
};

// Everything report.html shows, gathered from a run directory (run.json, trajectory.tum,
// stations.csv, metrics.json, mosaic.png, classification.png, points_sparse.ply,
// junctions.yaml, observations_located.csv) and its dataset's ground truth: the JSON of
// docs/formats.md "report.html" (schema pipescope-report/1). Images and point clouds go in as
// base64. Throws InputError naming the file when the run directory is not one.
nlohmann::json BuildReportData(const std::filesystem::path& run_dir, const ReportOptions& options);

}  // namespace pipescope
