#include "pipescope/eval/dense_map_evaluation.h"

#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "pipescope/io/association.h"
#include "pipescope/util/error.h"

namespace pipescope {
namespace {

Eigen::Vector3d Vector(const nlohmann::json& value) {
  return Eigen::Vector3d(value.at(0).get<double>(), value.at(1).get<double>(),
                         value.at(2).get<double>());
}

}  // namespace

std::vector<DensePieceAgreement> EvaluateDenseMap(const std::filesystem::path& run,
                                                  const Trajectory& ground_truth,
                                                  const Simulation& simulation, double max_dt_s,
                                                  const DenseMapAgreementOptions& options) {
  const std::filesystem::path report_path = run / "run.json";
  std::ifstream in(report_path);
  if (!in) throw InputError(report_path.string() + ": cannot be read");
  nlohmann::json report;
  try {
    report = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& error) {
    throw InputError(report_path.string() + ": not JSON: " + error.what());
  }
  const Trajectory keyframes = ReadTumTrajectory(run / "keyframes.tum");
  // The true pose of each key frame that has one within max_dt_s.
  std::vector<const StampedPose*> truth_of(keyframes.size(), nullptr);
  for (const AssociatedPair& pair : AssociateByTimestamp(ground_truth, keyframes, max_dt_s)) {
    truth_of[pair.est_index] = &ground_truth[pair.gt_index];
  }
  std::vector<DensePieceAgreement> results;
  try {
    const nlohmann::json& dense = report.at("dense_map");
    const double spacing = dense.at("spacing_m").get<double>();
    const double radius = report.at("options").at("radius_m").get<double>();
    std::map<int, cv::Mat> mosaics;  // by section
    std::map<int, int> next_row;     // the next piece's first row in its section's mosaic
    for (const nlohmann::json& entry : dense.at("mosaics")) {
      const std::filesystem::path file = run / entry.at("file").get<std::string>();
      cv::Mat mosaic = cv::imread(file.string(), cv::IMREAD_GRAYSCALE);
      if (mosaic.empty()) throw InputError(file.string() + ": cannot be read as an image");
      mosaics[entry.at("section").get<int>()] = mosaic;
    }
    const nlohmann::json& pieces = dense.at("pieces");
    for (std::size_t index = 0; index < pieces.size(); ++index) {
      const nlohmann::json& piece = pieces[index];
      DenseMapCylinder cylinder;
      cylinder.axis_point = Vector(piece.at("axis_point"));
      cylinder.axis_direction = Vector(piece.at("axis_direction"));
      cylinder.reference_direction = Vector(piece.at("reference_direction"));
      cylinder.radius_m = radius;
      cylinder.begin_m = piece.at("begin_m").get<double>();
      cylinder.end_m = piece.at("end_m").get<double>();
      const DenseMapGrid grid(cylinder, spacing);
      const int section = piece.at("section").get<int>();
      const auto mosaic = mosaics.find(section);
      const int first_row = next_row[section];
      if (mosaic == mosaics.end() || mosaic->second.cols != grid.cols() ||
          first_row + grid.rows() > mosaic->second.rows) {
        throw InputError(report_path.string() + ": dense_map piece " + std::to_string(index) +
                         " (" + std::to_string(grid.rows()) + " x " + std::to_string(grid.cols()) +
                         " cells) does not fit its section's mosaic");
      }
      next_row[section] = first_row + grid.rows();
      const cv::Mat grey = mosaic->second.rowRange(first_row, first_row + grid.rows());

      // Each row goes into the scene through the key frame of the piece nearest it along the
      // axis, and is looked at from that key frame's true position: the map placed locally, as
      // a camera there saw it, so the odometry's drift over the piece (a few millimetres, which
      // the trajectory's metrics measure) and the fitted axis's tilt, which turns into a shift
      // along the pipe where the wall is seen at a grazing angle, do not count as appearance.
      const int first = piece.at("first_keyframe").get<int>();
      const int last = piece.at("last_keyframe").get<int>();
      if (first < 0 || last < first || last >= static_cast<int>(keyframes.size())) {
        throw InputError(report_path.string() + ": dense_map piece " + std::to_string(index) +
                         " names key frames " + std::to_string(first) + "-" + std::to_string(last) +
                         " of " + std::to_string(keyframes.size()) + " in keyframes.tum");
      }
      std::vector<double> along;  // each key frame's estimated position along the piece's axis
      std::vector<GridRowPlacement> placements;
      for (int k = first; k <= last; ++k) {
        const StampedPose& estimated = keyframes[k];
        const StampedPose* truth = truth_of[k];
        if (truth == nullptr) {
          throw InputError("--gt: no pose within " + std::to_string(max_dt_s) + " s of key frame " +
                           std::to_string(k) + " (t = " + std::to_string(estimated.timestamp) +
                           " s)");
        }
        along.push_back((estimated.position - grid.axis_point()).dot(grid.axis_direction()));
        placements.push_back(
            {ToIsometry(*truth) * ToIsometry(estimated).inverse(), truth->position});
      }
      std::vector<GridRowPlacement> rows;
      for (int row = 0; row < grid.rows(); ++row) {
        const double s = grid.AxialPositionM(row);
        std::size_t nearest = 0;
        for (std::size_t k = 1; k < along.size(); ++k) {
          if (std::abs(along[k] - s) < std::abs(along[nearest] - s)) nearest = k;
        }
        rows.push_back(placements[nearest]);
      }
      // A cell more than a tenth of the radius off the wall it was placed on is not the wall.
      const cv::Mat albedo = SimulatedAlbedoUnderGrid(grid, rows, simulation, 0.1 * radius);

      DensePieceAgreement result;
      result.piece = static_cast<int>(index);
      result.section = section;
      result.part = piece.at("part").get<std::string>();
      result.keyframes_used = piece.value("keyframes_used", 0);
      result.agreement = CorrelateWithAlbedo(grey, albedo, grid, options);
      results.push_back(result);
    }
  } catch (const nlohmann::json::exception& error) {
    throw InputError(report_path.string() + ": dense_map: " + error.what());
  }
  return results;
}

}  // namespace pipescope
