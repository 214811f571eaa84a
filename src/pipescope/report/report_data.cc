#include "pipescope/report/report_data.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "pipescope/camera/camera_io.h"
#include "pipescope/eval/alignment.h"
#include "pipescope/geometry/clock_position.h"
#include "pipescope/io/association.h"
#include "pipescope/io/dataset.h"
#include "pipescope/io/image_source.h"
#include "pipescope/io/junctions.h"
#include "pipescope/io/point_cloud_ply.h"
#include "pipescope/report/observations.h"
#include "pipescope/report/run_files.h"
#include "pipescope/util/atomic_file.h"
#include "pipescope/util/base64.h"
#include "pipescope/util/error.h"
#include "pipescope/util/run_report.h"

namespace pipescope {
namespace {

using nlohmann::json;

// The viewer draws the trajectory as a line; more vertices than this add nothing visible.
constexpr std::size_t kMaxTrajectoryVertices = 20000;
// The dense wall cloud keeps at most about this many of the unrolled wall's cells.
constexpr double kMaxWallCells = 2e6;
// Half the side of an observation's crop, pixels (frame) and cells (unrolled wall).
constexpr int kCropHalfPx = 64;

std::string FileBytes(const std::filesystem::path& path) {
  return ReadTextFile(path);  // binary-safe: the whole file as bytes
}

json OrNull(double value) { return std::isfinite(value) ? json(value) : json(nullptr); }

std::string UtcNow() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  char text[32];
  std::strftime(text, sizeof(text), "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  return text;
}

std::string PngDataUrl(const cv::Mat& image) {
  std::vector<uchar> png;
  cv::imencode(".png", image, png);
  return DataUrl("image/png",
                 std::string_view(reinterpret_cast<const char*>(png.data()), png.size()));
}

template <typename T>
std::string Base64Of(const std::vector<T>& values) {
  return Base64Encode(
      std::string_view(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T)));
}

// The dataset whose ground truth and frames the report shows: --dataset, else run.json's.
std::optional<DatasetManifest> ReportDataset(const RunFiles& run, const ReportOptions& options) {
  if (!options.dataset.empty()) return OpenDataset(options.dataset);
  const json& inputs = run.run_json.at("inputs");
  if (!inputs.contains("dataset") || !inputs["dataset"].is_string()) return std::nullopt;
  const std::filesystem::path dataset = inputs["dataset"].get<std::string>();
  if (!std::filesystem::exists(dataset)) return std::nullopt;
  try {
    DatasetOverrides overrides;
    if (!std::filesystem::is_regular_file(dataset)) {
      overrides.camera_path = run.dir / "camera.yaml";
      overrides.inner_radius_m = run.radius_m;
    }
    return OpenDataset(dataset, overrides);
  } catch (const InputError& error) {
    // The dataset changed since the run: the report shows the run alone, and says why.
    spdlog::warn("the report shows no ground truth or frame crops: {} (give --dataset)",
                 error.what());
    return std::nullopt;
  }
}

// Consecutive frames of one state, from run.json's quality lists.
json Stretches(const json& quality, const RunFiles& run) {
  json stretches = json::array();
  const std::pair<const char*, const char*> lists[] = {{"predicted_frames", "predicted"},
                                                       {"bridged_frames", "bridged"},
                                                       {"not_localised_frames", "not_localised"}};
  for (const auto& [key, state] : lists) {
    if (!quality.contains(key)) continue;
    std::vector<int> frames = quality[key].get<std::vector<int>>();
    std::sort(frames.begin(), frames.end());
    for (std::size_t i = 0; i < frames.size();) {
      std::size_t j = i;
      while (j + 1 < frames.size() && frames[j + 1] == frames[j] + 1) ++j;
      json stretch = {{"state", state}, {"first_frame", frames[i]}, {"last_frame", frames[j]}};
      const Station* first = run.StationOfFrame(frames[i]);
      const Station* last = run.StationOfFrame(frames[j]);
      stretch["t_from"] = first ? json(first->timestamp) : json(nullptr);
      stretch["t_to"] = last ? json(last->timestamp) : json(nullptr);
      stretch["distance_from_m"] = first ? json(first->distance_m) : json(nullptr);
      stretch["distance_to_m"] = last ? json(last->distance_m) : json(nullptr);
      stretches.push_back(stretch);
      i = j + 1;
    }
  }
  return stretches;
}

json StationsJson(const RunFiles& run, const json& quality) {
  std::map<int, std::string> states;
  for (const auto& [key, state] :
       {std::pair<const char*, const char*>{"predicted_frames", "predicted"},
        {"bridged_frames", "bridged"}}) {
    if (!quality.contains(key)) continue;
    for (int frame : quality[key].get<std::vector<int>>()) states[frame] = state;
  }
  json frame = json::array(), t = json::array(), x = json::array(), y = json::array(),
       z = json::array(), distance = json::array(), speed = json::array(), roll = json::array(),
       state = json::array();
  for (const Station& station : run.stations) {
    frame.push_back(station.frame);
    t.push_back(station.timestamp);
    x.push_back(station.position.x());
    y.push_back(station.position.y());
    z.push_back(station.position.z());
    distance.push_back(station.distance_m);
    speed.push_back(station.speed_m_s);
    roll.push_back(OrNull(station.roll_clock_deg));
    const auto found = states.find(station.frame);
    state.push_back(found == states.end() ? "measured" : found->second);
  }
  return {{"frame", frame},
          {"t", t},
          {"x", x},
          {"y", y},
          {"z", z},
          {"distance_m", distance},
          {"speed_m_s", speed},
          {"roll_clock_deg", roll},
          {"state", state}};
}

// The truth at each estimated station: positions (in the run's frame, through the SE(3)
// alignment of metrics.json), distance along the pipe on the same survey line, position error
// after that alignment, distance error.
json GroundTruthJson(const RunFiles& run, const DatasetManifest& dataset) {
  if (dataset.groundtruth_path.empty()) return nullptr;
  const Trajectory truth = ReadTumTrajectory(dataset.groundtruth_path);
  const std::vector<AssociatedPair> pairs = AssociateByTimestamp(truth, run.trajectory);
  if (pairs.size() < 2) return nullptr;
  StationOptions options = run.station_options;
  if (dataset.pipe_up && options.line == SurveyLine::kStraightAxis) options.up = *dataset.pipe_up;
  const std::vector<Station> true_stations =
      ComputeStations(truth, std::vector<int>(truth.size(), -1), options);
  std::vector<Eigen::Vector3d> estimated, actual;
  for (const AssociatedPair& pair : pairs) {
    estimated.push_back(run.trajectory[pair.est_index].position);
    actual.push_back(truth[pair.gt_index].position);
  }
  const SimilarityTransform align = AlignPositions(estimated, actual, Alignment::kSe3);
  // Distances count from the run's first pose: the truth's from the pose matched to it.
  const double true_start = true_stations[pairs.front().gt_index].distance_m -
                            run.stations[pairs.front().est_index].distance_m;
  json t = json::array(), x = json::array(), y = json::array(), z = json::array(),
       distance = json::array(), position_error = json::array(), distance_error = json::array();
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const Station& truth_station = true_stations[pairs[k].gt_index];
    const Station& estimate = run.stations[pairs[k].est_index];
    t.push_back(truth_station.timestamp);
    // Drawn beside the estimate: the truth in the run's frame (the alignment undone).
    const Eigen::Vector3d in_run =
        align.rotation.transpose() * (truth_station.position - align.translation) / align.scale;
    x.push_back(in_run.x());
    y.push_back(in_run.y());
    z.push_back(in_run.z());
    const double true_distance = truth_station.distance_m - true_start;
    distance.push_back(true_distance);
    position_error.push_back((align(estimated[k]) - actual[k]).norm());
    distance_error.push_back(estimate.distance_m - true_distance);
  }
  return {{"t", t},
          {"x", x},
          {"y", y},
          {"z", z},
          {"distance_m", distance},
          {"position_error_m", position_error},
          {"distance_error_m", distance_error}};
}

// The clock angle of the unrolled wall's row `v` (s = r phi from the pipe frame's X axis).
double RowClockDeg(double s0_m, double pixel_m, double v, const RunFiles& run) {
  const double phi = (s0_m + v * pixel_m) / run.radius_m;
  return ClockAngleDeg({std::cos(phi), std::sin(phi), 0.0}, run.stations.front().travel,
                       run.station_options.up)
      .value_or(std::numeric_limits<double>::quiet_NaN());
}

json MosaicsJson(const RunFiles& run) {
  json mosaics = json::array();
  const auto png = run.File("mosaic.png");
  if (!png || !run.run_json.contains("mosaic")) return mosaics;
  const json& mosaic = run.run_json["mosaic"];
  json entry = {{"title", "Unrolled wall"},
                {"image", DataUrl("image/png", FileBytes(*png))},
                {"width_px", mosaic.value("width_px", 0)},
                {"height_px", mosaic.value("height_px", 0)},
                {"metric", false},
                {"distance_m_at_col0", nullptr},
                {"distance_m_per_col", nullptr},
                {"clock_deg_at_row0", nullptr},
                {"clock_deg_per_row", nullptr},
                {"note", ""}};
  const bool unrolled = mosaic.value("kind", "") == "unrolled" && mosaic["pixel_m"].is_number() &&
                        run.station_options.line == SurveyLine::kStraightAxis;
  if (mosaic.value("kind", "") == "tube-unrolled") {
    // ekf: the tube dewarped along its estimated centreline, through the bends.
    entry["title"] = "Dewarped tube (along the centreline)";
    entry["note"] =
        "Columns run along the estimated centreline through the bends, rows around the tube "
        "from 12 o'clock through 9, 6 and 3 (docs/ekf.md); distance on it is the centreline's, "
        "not the survey line's, so it carries no ruler here.";
    mosaics.push_back(entry);
    return mosaics;
  }
  if (!unrolled) {
    entry["title"] = "Appearance map (image space)";
    entry["note"] =
        "This method stitches frames in image space: the map has no metric scale, so "
        "it carries no distance ruler or clock positions.";
    mosaics.push_back(entry);
    return mosaics;
  }
  const double pixel_m = mosaic["pixel_m"].get<double>();
  const double h0 = mosaic.value("origin_h_m", 0.0);
  const double s0 = mosaic.value("origin_s_m", 0.0);
  const Station& start = run.stations.front();
  const double travel_z = start.travel.z();
  entry["metric"] = true;
  entry["distance_m_at_col0"] = (h0 - start.position.z()) * travel_z;
  entry["distance_m_per_col"] = pixel_m * travel_z;
  const double clock0 = RowClockDeg(s0, pixel_m, 0.0, run);
  double per_row = RowClockDeg(s0, pixel_m, 1.0, run) - clock0;
  per_row = std::remainder(per_row, 360.0);
  entry["clock_deg_at_row0"] = OrNull(clock0);
  entry["clock_deg_per_row"] = OrNull(per_row);
  entry["note"] = "Columns run along the pipe (" + std::to_string(pixel_m * 1000.0).substr(0, 5) +
                  " mm each), rows around it; each cell is the mean of the frames that saw it.";
  mosaics.push_back(entry);
  return mosaics;
}

json ClassificationJson(const RunFiles& run) {
  const auto png = run.File("classification.png");
  if (!png) return nullptr;
  json keyframes = json::array();
  if (run.run_json.contains("keyframes")) {
    for (const json& keyframe : run.run_json["keyframes"]) {
      const int frame = keyframe.value("frame", -1);
      const Station* station = run.StationOfFrame(frame);
      keyframes.push_back({{"frame", frame},
                           {"t", station ? json(station->timestamp) : json(nullptr)},
                           {"distance_m", station ? json(station->distance_m) : json(nullptr)},
                           {"class", keyframe.value("class", "")},
                           {"section", keyframe.value("section", -1)}});
    }
  }
  return {{"image", DataUrl("image/png", FileBytes(*png))}, {"keyframes", keyframes}};
}

// A table row per section: scalar fields as they are, short number lists joined.
json SectionsJson(const RunFiles& run) {
  json rows = json::array();
  if (!run.run_json.contains("sections") || !run.run_json["sections"].is_array()) return rows;
  for (const json& section : run.run_json["sections"]) {
    json row = json::object();
    for (const auto& [key, value] : section.items()) {
      if (value.is_primitive()) {
        row[key] = value;
      } else if (value.is_array() && value.size() <= 4) {
        std::string joined;
        for (const json& item : value) joined += (joined.empty() ? "" : ", ") + item.dump();
        row[key] = joined;
      }
    }
    rows.push_back(row);
  }
  return rows;
}

const Station* NearestStationInTime(const RunFiles& run, double t) {
  const Station* best = nullptr;
  for (const Station& station : run.stations) {
    if (best == nullptr || std::abs(station.timestamp - t) < std::abs(best->timestamp - t))
      best = &station;
  }
  return best;
}

json JunctionsJson(const RunFiles& run) {
  json rows = json::array();
  const auto yaml = run.File("junctions.yaml");
  if (!yaml) return rows;
  for (const Junction& junction : ReadEstimatedJunctions(*yaml)) {
    const Station* station =
        std::isfinite(junction.timestamp) ? NearestStationInTime(run, junction.timestamp) : nullptr;
    rows.push_back({{"name", junction.name},
                    {"t", OrNull(junction.timestamp)},
                    {"distance_m", station ? json(station->distance_m) : json(nullptr)},
                    {"center", {junction.center.x(), junction.center.y(), junction.center.z()}}});
  }
  return rows;
}

cv::Mat CropAround(const cv::Mat& image, double u, double v, const cv::Rect& box) {
  cv::Rect around(static_cast<int>(std::lround(u)) - kCropHalfPx,
                  static_cast<int>(std::lround(v)) - kCropHalfPx, 2 * kCropHalfPx, 2 * kCropHalfPx);
  around |= box;
  around &= cv::Rect(0, 0, image.cols, image.rows);
  if (around.empty()) return {};
  cv::Mat crop;
  cv::cvtColor(image(around), crop,
               image.channels() == 1 ? cv::COLOR_GRAY2BGR : cv::COLOR_BGRA2BGR);
  const cv::Point offset = around.tl();
  if (box.area() > 0) {
    cv::rectangle(crop, box - offset, cv::Scalar(0, 140, 255), 1);
  } else {
    cv::circle(crop, cv::Point(std::lround(u), std::lround(v)) - offset, 6, cv::Scalar(0, 140, 255),
               1);
  }
  return crop;
}

json ObservationsJson(const RunFiles& run, const std::optional<DatasetManifest>& dataset) {
  json rows = json::array();
  const auto csv = run.File("observations_located.csv");
  if (!csv) return rows;
  std::vector<std::filesystem::path> frames;
  if (dataset && !dataset->images_dir.empty()) frames = ListImageFiles(dataset->images_dir);
  cv::Mat mosaic;
  const json* mosaic_json = run.run_json.contains("mosaic") ? &run.run_json["mosaic"] : nullptr;
  if (const auto png = run.File("mosaic.png");
      png && mosaic_json && mosaic_json->value("kind", "") == "unrolled") {
    mosaic = cv::imread(png->string(), cv::IMREAD_UNCHANGED);
  }
  int id = 0;
  for (const LocatedObservation& entry : ReadLocatedObservationsCsv(*csv)) {
    const Observation& o = entry.observation;
    json row = {{"id", ++id},
                {"frame", o.frame},
                {"u", o.u()},
                {"v", o.v()},
                {"code", o.code},
                {"remark", o.remark},
                {"distance_m", entry.located ? OrNull(entry.centre.distance_m) : json(nullptr)},
                {"clock", entry.centre.clock},
                {"clock_angle_deg", OrNull(entry.centre.clock_angle_deg)},
                {"clock_from", entry.clock_from},
                {"clock_to", entry.clock_to},
                {"section", entry.located ? json(entry.centre.section) : json(nullptr)},
                {"note", entry.why_not},
                {"crop_frame", nullptr},
                {"crop_wall", nullptr}};
    if (o.frame >= 0 && static_cast<std::size_t>(o.frame) < frames.size()) {
      const cv::Mat image = cv::imread(frames[o.frame].string(), cv::IMREAD_COLOR);
      const cv::Rect box = o.box ? cv::Rect(cv::Point(std::lround(o.u_min), std::lround(o.v_min)),
                                            cv::Point(std::lround(o.u_max), std::lround(o.v_max)))
                                 : cv::Rect();
      if (!image.empty()) {
        const cv::Mat crop = CropAround(image, o.u(), o.v(), box);
        if (!crop.empty()) row["crop_frame"] = PngDataUrl(crop);
      }
    }
    if (!mosaic.empty() && entry.located && entry.centre.point.allFinite()) {
      // The wall point's cell: h along the columns, s = r phi (phi from X in [0, 2 pi)) down.
      const double pixel_m = mosaic_json->at("pixel_m").get<double>();
      double phi = std::atan2(entry.centre.point.y(), entry.centre.point.x());
      if (phi < 0.0) phi += 2.0 * M_PI;
      const double col = (entry.centre.point.z() - mosaic_json->value("origin_h_m", 0.0)) / pixel_m;
      const double row_cell =
          (run.radius_m * phi - mosaic_json->value("origin_s_m", 0.0)) / pixel_m;
      if (col >= 0 && col < mosaic.cols && row_cell >= 0 && row_cell < mosaic.rows) {
        const cv::Mat crop = CropAround(mosaic, col, row_cell, cv::Rect());
        if (!crop.empty()) row["crop_wall"] = PngDataUrl(crop);
      }
    }
    rows.push_back(row);
  }
  return rows;
}

// The unrolled wall as a dense 3D appearance map of the straight pipe: each covered cell of
// mosaic.png at its wall point (r cos phi, r sin phi, h), with its grey value (000 §6.1 maps the
// wall this way; 0 is an empty cell of the PNG). Every `stride`-th cell along both axes.
bool AddWallCells(const RunFiles& run, std::vector<float>* positions,
                  std::vector<std::uint8_t>* grey) {
  const auto png = run.File("mosaic.png");
  if (!png || !run.run_json.contains("mosaic") || run.radius_m <= 0.0) return false;
  const json& mosaic = run.run_json["mosaic"];
  if (mosaic.value("kind", "") != "unrolled" || !mosaic["pixel_m"].is_number()) return false;
  const cv::Mat image = cv::imread(png->string(), cv::IMREAD_GRAYSCALE);
  if (image.empty()) return false;
  const double pixel_m = mosaic["pixel_m"].get<double>();
  const double h0 = mosaic.value("origin_h_m", 0.0), s0 = mosaic.value("origin_s_m", 0.0);
  const int stride = std::max(
      1,
      static_cast<int>(std::ceil(std::sqrt(static_cast<double>(image.total()) / kMaxWallCells))));
  for (int v = 0; v < image.rows; v += stride) {
    const double phi = (s0 + v * pixel_m) / run.radius_m;
    for (int u = 0; u < image.cols; u += stride) {
      const std::uint8_t value = image.at<std::uint8_t>(v, u);
      if (value == 0) continue;
      positions->insert(positions->end(), {static_cast<float>(run.radius_m * std::cos(phi)),
                                           static_cast<float>(run.radius_m * std::sin(phi)),
                                           static_cast<float>(h0 + u * pixel_m)});
      grey->push_back(value);
    }
  }
  return true;
}

json CloudJson(const RunFiles& run) {
  std::vector<float> positions;
  std::vector<std::uint8_t> grey;
  json sections = nullptr;
  std::string kind;
  if (AddWallCells(run, &positions, &grey)) {
    kind = "the unrolled wall's cells on the pipe's cylinder, grey values of mosaic.png";
  } else if (const auto ply = run.File("points_sparse.ply")) {
    const PlyPoints cloud = ReadPlyPoints(*ply);
    for (const Eigen::Vector3d& p : cloud.points) {
      positions.insert(positions.end(), {static_cast<float>(p.x()), static_cast<float>(p.y()),
                                         static_cast<float>(p.z())});
    }
    kind = "sparse points (points_sparse.ply)";
    // Colours of a map's cloud stand for its sections: number them in order of appearance.
    if (!cloud.colours.empty()) {
      std::map<PlyColour, std::uint16_t> numbers;
      std::vector<std::uint16_t> ids;
      for (const PlyColour& colour : cloud.colours) {
        const auto [it, added] =
            numbers.emplace(colour, static_cast<std::uint16_t>(numbers.size()));
        ids.push_back(it->second);
      }
      sections = Base64Of(ids);
    }
  } else {
    return nullptr;
  }
  std::vector<float> path;
  const std::size_t stride =
      std::max<std::size_t>(1, run.trajectory.size() / kMaxTrajectoryVertices);
  for (std::size_t i = 0; i < run.trajectory.size(); i += stride) {
    const Eigen::Vector3d& p = run.trajectory[i].position;
    path.insert(path.end(),
                {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())});
  }
  json junctions = json::array();
  for (const json& junction : JunctionsJson(run)) {
    junctions.push_back({{"name", junction["name"]}, {"center", junction["center"]}});
  }
  return {{"count", positions.size() / 3},
          {"kind", kind},
          {"positions_f32", Base64Of(positions)},
          {"grey_u8", grey.empty() ? json(nullptr) : json(Base64Of(grey))},
          {"section_u16", sections},
          {"trajectory_f32", Base64Of(path)},
          {"junctions", junctions}};
}

json QualityJson(const RunFiles& run) {
  json quality = run.run_json.value("quality", json::object());
  json out = {
      {"verdict", quality.value("verdict", json(nullptr))},
      {"reasons", quality.value("reasons", json::array())},
      {"along_pipe_verdict", quality.value("along_pipe_verdict", json(nullptr))},
      {"frames_measured", quality.value("frames_measured", json(nullptr))},
      {"frames_bridged", quality.value("frames_bridged", json(nullptr))},
      {"frames_predicted", quality.value("frames_predicted", json(nullptr))},
      {"frames_not_localised", quality.value("frames_not_localised", json(nullptr))},
      {"longest_predicted_stretch", quality.value("longest_predicted_stretch", json(nullptr))},
      {"stretches", Stretches(quality, run)}};
  return out;
}

}  // namespace

json BuildReportData(const std::filesystem::path& run_dir, const ReportOptions& options) {
  const RunFiles run = ReadRunFiles(run_dir);
  const std::optional<DatasetManifest> dataset = ReportDataset(run, options);
  const json& run_json = run.run_json;
  const json counts = run_json.value("counts", json::object());
  double travelled = 0.0;
  for (std::size_t i = 1; i < run.trajectory.size(); ++i) {
    travelled += (run.trajectory[i].position - run.trajectory[i - 1].position).norm();
  }
  double low = 0.0, high = 0.0;
  for (const Station& station : run.stations) {
    low = std::min(low, station.distance_m);
    high = std::max(high, station.distance_m);
  }
  const std::string method = run_json.value("method", "");
  const std::string dataset_name = dataset ? dataset->name : std::string("dataset not found");
  json data;
  data["schema"] = "pipescope-report/1";
  data["title"] = "pipescope " + run.command + ": " + method + " on " + dataset_name;
  data["generated"] = {{"by", std::string("pipescope ") + PipescopeVersion()}, {"utc", UtcNow()}};
  data["run"] = {
      {"command", run.command},
      {"method", method},
      {"directory", std::filesystem::absolute(
                        options.shown_directory.empty() ? run_dir : options.shown_directory)
                        .string()},
      {"dataset", dataset ? json(std::filesystem::absolute(dataset->manifest_path.empty()
                                                               ? dataset->images_dir
                                                               : dataset->manifest_path)
                                     .string())
                          : json(nullptr)},
      {"frames", counts.value("frames", static_cast<long long>(run.trajectory.size()))},
      {"frames_localised", run.trajectory.size()},
      {"duration_s", run.trajectory.back().timestamp - run.trajectory.front().timestamp},
      {"distance_travelled_m", travelled},
      {"distance_min_m", low},
      {"distance_max_m", high},
      {"radius_m", run.radius_m},
      {"timings_s", run_json.value("timings_s", json::object())}};
  data["quality"] = QualityJson(run);
  data["warnings"] = run_json.value("warnings", json::array());
  const Eigen::Vector3d& up = run.station_options.up;
  data["convention"] = {
      {"distance",
       run.station_options.line == SurveyLine::kStraightAxis
           ? "Distance along the pipe's axis from the camera's position at the first frame, "
             "positive in the direction the crawler first moved (kept when it turns back)."
           : "Distance along the path travelled from the first frame, each step projected on "
             "the local direction of the pipe."},
      {"clock",
       "Clock position looking along that direction: 12 o'clock at the top of the pipe, 3 "
       "o'clock to the right."},
      {"up_source", "Top of the pipe: " + run.up_source + "."},
      {"up", {up.x(), up.y(), up.z()}}};
  data["stations"] = StationsJson(run, run_json.value("quality", json::object()));
  data["ground_truth"] = dataset ? GroundTruthJson(run, *dataset) : json(nullptr);
  if (const auto metrics = run.File("metrics.json")) {
    data["metrics"] = json::parse(ReadTextFile(*metrics));
  } else {
    data["metrics"] = nullptr;
  }
  data["mosaics"] = MosaicsJson(run);
  data["classification"] = ClassificationJson(run);
  data["sections"] = SectionsJson(run);
  data["junctions"] = JunctionsJson(run);
  data["t_to_t"] = json::array();
  data["observations"] = ObservationsJson(run, dataset);
  data["cloud"] = CloudJson(run);
  return data;
}

}  // namespace pipescope
