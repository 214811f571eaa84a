// `pipescope map`: fisheye pipe mapping (001 §III A-C), writing a run directory (GUIDE §4):
// trajectory.tum, keyframes.tum, points_sparse.ply, classification.png, run.json and, with
// ground truth, metrics.json.
#include <glog/logging.h>
#include <spdlog/spdlog.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <string>

#include "pipescope/camera/camera_io.h"
#include "pipescope/cli/subcommand.h"
#include "pipescope/eval/metrics_report.h"
#include "pipescope/eval/trajectory_metrics.h"
#include "pipescope/io/dataset.h"
#include "pipescope/io/point_cloud_ply.h"
#include "pipescope/io/trajectory.h"
#include "pipescope/pipeline/fisheye_mapping.h"
#include "pipescope/util/atomic_file.h"
#include "pipescope/util/error.h"
#include "pipescope/util/run_report.h"
#include "pipescope/util/staging_directory.h"
#include "pipescope/util/timer.h"

namespace pipescope {
namespace {

struct MapFlags {
  std::string dataset;
  std::string out;
  std::string config;
  std::string camera;
  std::optional<double> radius;
};

// The --config keys, each bound to one option.
std::map<std::string, double*> DoubleKeys(FisheyeMappingOptions* o) {
  return {{"tau", &o->window.tau},
          {"huber_px", &o->window.huber_px},
          {"mad_factor", &o->window.mad_factor},
          {"min_median_flow_px", &o->tracking.min_median_flow_px},
          {"min_correspondence_fraction", &o->tracking.min_correspondence_fraction},
          {"min_similarity", &o->tracking.matching.min_similarity},
          {"inlier_threshold_rad", &o->tracking.relative_pose.inlier_threshold_rad},
          {"min_zncc", &o->tracking.guided.min_zncc},
          {"max_straight_moment_ratio", &o->classification.max_straight_moment_ratio},
          {"dark_fraction_of_median", &o->classification.dark_fraction_of_median},
          {"max_view_angle_deg", &o->tracking.max_view_angle_deg},
          {"min_triangulation_angle_deg", &o->min_triangulation_angle_deg},
          {"min_scale_parallax_rad", &o->min_scale_parallax_rad},
          {"max_step_change", &o->max_step_change},
          {"max_window_length_change", &o->max_window_length_change},
          {"max_window_cylinder_rms", &o->max_window_cylinder_rms},
          {"max_window_rms_px", &o->max_window_rms_px},
          {"max_window_start_error_px", &o->max_window_start_error_px},
          {"max_step_direction_change_deg", &o->max_step_direction_change_deg},
          {"max_window_speed_ratio", &o->max_window_speed_ratio},
          {"axis_prior_sigma_deg", &o->window.axis_prior_sigma_deg},
          {"axis_prior_sigma_m", &o->window.axis_prior_sigma_m},
          {"first_rotation_sigma_deg", &o->window.first_rotation_sigma_deg}};
}
std::map<std::string, int*> IntKeys(FisheyeMappingOptions* o) {
  return {
      {"window_interval", &o->window_interval},
      {"window_size", &o->window_size},
      {"min_cluster_size", &o->min_cluster_size},
      {"per_region", &o->tracking.harris.per_cell},
      {"stages", &o->window.stages},
      {"max_iterations_per_stage", &o->window.max_iterations_per_stage},
      {"max_iterations_before_outlier_removal", &o->window.max_iterations_before_outlier_removal},
      {"min_cylinder_scale_points", &o->min_cylinder_scale_points},
      {"speed_history", &o->speed_history},
      {"stale_axis_keyframes", &o->stale_axis_keyframes},
      {"window_threads", &o->window.num_threads}};
}

void ApplyMapConfig(const std::string& path, FisheyeMappingOptions* options) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const std::exception& error) {
    throw InputError("--config " + path + ": " + error.what());
  }
  if (!root.IsMap()) throw InputError("--config " + path + ": expected a map of option: value");
  auto doubles = DoubleKeys(options);
  auto ints = IntKeys(options);
  for (const auto& entry : root) {
    const std::string key = entry.first.as<std::string>();
    try {
      if (doubles.count(key)) {
        *doubles[key] = entry.second.as<double>();
      } else if (ints.count(key)) {
        *ints[key] = entry.second.as<int>();
      } else if (key == "guided_matching") {
        options->tracking.guided_matching = entry.second.as<bool>();
      } else if (key == "use_cylinder") {
        options->window.use_cylinder = entry.second.as<bool>();
      } else if (key == "fit_axis_per_step") {
        options->fit_axis_per_step = entry.second.as<bool>();
      } else if (key == "refine_pose_on_structure") {
        options->refine_pose_on_structure = entry.second.as<bool>();
      } else if (key == "retriangulate_in_window") {
        options->retriangulate_in_window = entry.second.as<bool>();
      } else if (key == "axis_prior") {
        options->axis_prior = entry.second.as<bool>();
      } else if (key == "overlap_odometry") {
        options->overlap_odometry = entry.second.as<bool>();
      } else {
        throw InputError("--config " + path + ": unknown key '" + key + "'");
      }
    } catch (const YAML::Exception&) {
      throw InputError("--config " + path + ": key '" + key + "' has a malformed value");
    }
  }
  if (options->window_interval < 1 || options->window_size < 3 || options->speed_history < 1 ||
      options->window.num_threads < 1) {
    throw InputError("--config " + path +
                     ": window_interval must be >= 1, window_size >= 3, speed_history >= 1, "
                     "window_threads >= 1");
  }
}

nlohmann::json OptionsJson(FisheyeMappingOptions options) {
  nlohmann::json json;
  for (const auto& [key, value] : DoubleKeys(&options)) json[key] = *value;
  for (const auto& [key, value] : IntKeys(&options)) json[key] = *value;
  json["guided_matching"] = options.tracking.guided_matching;
  json["use_cylinder"] = options.window.use_cylinder;
  json["refine_pose_on_structure"] = options.refine_pose_on_structure;
  json["fit_axis_per_step"] = options.fit_axis_per_step;
  json["retriangulate_in_window"] = options.retriangulate_in_window;
  json["axis_prior"] = options.axis_prior;
  json["overlap_odometry"] = options.overlap_odometry;
  json["radius_m"] = options.window.radius_m;
  return json;
}

// points_sparse.ply: one colour per section (straight sections in alternating blues and greens,
// T-intersections red).
void WriteSparsePly(const std::filesystem::path& path, const FisheyeMappingResult& result) {
  static const PlyColour kStraightColours[4] = {
      {40, 90, 220}, {40, 180, 90}, {30, 160, 200}, {120, 200, 40}};
  std::vector<Eigen::Vector3d> positions;
  std::vector<PlyColour> colours;
  for (const SparsePoint& point : result.points) {
    const FisheyeSection& section = result.sections[point.section];
    positions.push_back(point.position);
    colours.push_back(section.view_class == PipeViewClass::kStraight
                          ? kStraightColours[point.section % 4]
                          : PlyColour{220, 40, 40});
  }
  WritePlyPoints(path, positions, colours, "pipescope map: sparse points, coloured by section");
}

// The ground-truth pose nearest in time, or nullptr beyond 1 ms.
const StampedPose* NearestPose(const Trajectory& trajectory, double timestamp) {
  const StampedPose* best = nullptr;
  for (const StampedPose& pose : trajectory) {
    if (std::abs(pose.timestamp - timestamp) < 1e-3 &&
        (!best || std::abs(pose.timestamp - timestamp) < std::abs(best->timestamp - timestamp))) {
      best = &pose;
    }
  }
  return best;
}

nlohmann::json SectionsJson(const FisheyeMappingResult& result, const Trajectory* ground_truth) {
  nlohmann::json sections = nlohmann::json::array();
  for (std::size_t s = 0; s < result.sections.size(); ++s) {
    const FisheyeSection& section = result.sections[s];
    const FisheyeKeyframe& first = result.keyframes[section.first_keyframe];
    const FisheyeKeyframe& last = result.keyframes[section.last_keyframe];
    const double est_m =
        (last.world_from_cam.translation() - first.world_from_cam.translation()).norm();
    nlohmann::json entry = {{"index", s},
                            {"class", PipeViewClassName(section.view_class)},
                            {"first_keyframe", section.first_keyframe},
                            {"last_keyframe", section.last_keyframe},
                            {"first_frame", first.frame_index},
                            {"last_frame", last.frame_index},
                            {"distance_est_m", est_m}};
    if (ground_truth) {
      const StampedPose* a = NearestPose(*ground_truth, first.timestamp);
      const StampedPose* b = NearestPose(*ground_truth, last.timestamp);
      if (a && b) {
        const double gt_m = (b->position - a->position).norm();
        entry["distance_gt_m"] = gt_m;
        entry["distance_error_pct"] =
            gt_m > 0 ? nlohmann::json(100.0 * (est_m - gt_m) / gt_m) : nlohmann::json(nullptr);
      }
    }
    sections.push_back(entry);
  }
  return sections;
}

int RunMap(const MapFlags& flags) {
  const Timer total;
  const ProcessCpuTimer total_cpu;
  // Ceres logs each rejected Levenberg-Marquardt step of a badly conditioned window as a
  // warning; the window statistics in run.json say what matters.
  FLAGS_minloglevel = google::GLOG_ERROR;
  DatasetManifest manifest = OpenDataset(
      flags.dataset, {.camera_path = flags.camera, .inner_radius_m = flags.radius, .fps = {}});
  FisheyeMappingOptions options;
  options.window.radius_m = RequireInnerRadius(manifest);
  if (!flags.config.empty()) ApplyMapConfig(flags.config, &options);
  const Camera camera = ReadCamera(manifest.camera_path);
  std::optional<Trajectory> ground_truth;
  if (!manifest.groundtruth_path.empty())
    ground_truth = ReadTumTrajectory(manifest.groundtruth_path);
  StagingDirectory staging(flags.out, "--out", "run.json");

  const FisheyeMappingResult result = RunFisheyeMapping(manifest, camera, options);
  if (result.keyframes.empty()) {
    throw InputError(flags.dataset + ": no frame could be used for mapping");
  }

  RunReport report("map");
  report.SetMethod("fisheye-sba-cylinder");
  report.SetOptions(OptionsJson(options));
  report.SetCount("frames",
                  result.frames + static_cast<long long>(result.unreadable_frames.size()));
  report.SetCount("frames_localised", static_cast<long long>(result.trajectory.size()));
  report.SetCount("frames_unusable", static_cast<long long>(result.failed_frames.size()));
  report.SetCount("frames_unreadable", static_cast<long long>(result.unreadable_frames.size()));
  report.SetCount("keyframes", static_cast<long long>(result.keyframes.size()));
  report.SetCount("points_sparse", static_cast<long long>(result.points.size()));
  report.SetCount("tracking_resets", result.tracking_resets);
  report.AddTiming("tracking", result.tracking_seconds);
  report.AddTiming("classification", result.classification_seconds);
  report.AddTiming("odometry", result.odometry_seconds);
  report.AddTiming("tracking_cpu", result.tracking_cpu_seconds);
  report.AddTiming("classification_cpu", result.classification_cpu_seconds);
  report.AddTiming("odometry_cpu", result.odometry_cpu_seconds);
  report.AddTiming("odometry_wait", result.odometry_wait_seconds);
  nlohmann::json classification = nlohmann::json::array();
  for (const FisheyeKeyframe& keyframe : result.keyframes) {
    classification.push_back({{"frame", keyframe.frame_index},
                              {"name", keyframe.name},
                              {"initial", PipeViewClassName(keyframe.initial_class)},
                              {"class", PipeViewClassName(keyframe.filtered_class)},
                              {"moment_ratio", std::isfinite(keyframe.moment_ratio)
                                                   ? nlohmann::json(keyframe.moment_ratio)
                                                   : nlohmann::json(nullptr)},
                              {"section", keyframe.section},
                              {"features", keyframe.features},
                              {"matches_cosine", keyframe.matches_cosine},
                              {"matches_guided", keyframe.matches_guided},
                              {"scale_points", keyframe.points_used},
                              {"direction_rejected", keyframe.direction_rejected},
                              {"median_flow_px", keyframe.median_flow_px}});
  }
  report.Extra("keyframes") = classification;
  report.Extra("sections") = SectionsJson(result, ground_truth ? &*ground_truth : nullptr);
  nlohmann::json windows = nlohmann::json::array();
  for (const FisheyeWindowRecord& window : result.windows) {
    windows.push_back({{"section", window.section},
                       {"first_keyframe", window.first_keyframe},
                       {"last_keyframe", window.last_keyframe},
                       {"points", window.points},
                       {"cylinder", window.cylinder},
                       {"rejected", !window.rejection.empty()},
                       {"rejection", window.rejection},
                       {"length_ratio", window.length_ratio},
                       {"observations", window.summary.observations},
                       {"outliers_removed", window.summary.outliers_removed},
                       {"initial_rms_px", window.summary.initial_rms_px},
                       {"final_rms_px", window.summary.final_rms_px},
                       {"cylinder_rms_m", window.summary.cylinder_rms_m},
                       {"seconds", window.summary.seconds}});
  }
  report.Extra("windows") = windows;
  nlohmann::json failed = nlohmann::json::array();
  for (const FisheyeFrameFailure& failure : result.failed_frames) {
    failed.push_back(
        {{"index", failure.index}, {"name", failure.name}, {"reason", failure.reason}});
  }
  report.Extra("failed_frames") = failed;
  report.Extra("unreadable_frames") = result.unreadable_frames;
  if (!result.failed_frames.empty()) {
    report.Warn(std::to_string(result.failed_frames.size()) +
                " frames could not be matched to their key frame and were skipped (see "
                "failed_frames)");
  }
  report.Extra("trajectory_note") =
      "key frame poses are estimated; other frames are interpolated between key frames; the "
      "world frame is the first key frame's camera frame";

  WriteTumTrajectory(staging.path() / "trajectory.tum", result.trajectory);
  WriteTumTrajectory(staging.path() / "keyframes.tum", result.keyframe_trajectory);
  WriteSparsePly(staging.path() / "points_sparse.ply", result);
  std::vector<PipeViewClass> initial, filtered;
  for (const FisheyeKeyframe& keyframe : result.keyframes) {
    initial.push_back(keyframe.initial_class);
    filtered.push_back(keyframe.filtered_class);
  }
  cv::imwrite((staging.path() / "classification.png").string(),
              DrawClassificationStrip(initial, filtered));
  if (ground_truth) {
    const Metrics metrics = EvaluateTrajectory(*ground_truth, result.trajectory, {});
    WriteTextFileAtomically(staging.path() / "metrics.json", MetricsToJson(metrics).dump(2) + "\n");
    std::cout << MetricsToTable(metrics);
  }
  const double seconds = total.ElapsedSeconds();
  report.AddTiming("total", seconds);
  report.AddTiming("total_cpu", total_cpu.ElapsedSeconds());
  report.Extra("fps_end_to_end") = result.frames / std::max(1e-9, seconds);
  report.Write(staging.path() / "run.json");
  staging.Commit();
  spdlog::info(
      "map: {} frames, {} key frames, {} sections, {} points in {:.1f} s ({:.2f} frames/s); wrote "
      "{}",
      result.frames, result.keyframes.size(), result.sections.size(), result.points.size(), seconds,
      result.frames / std::max(1e-9, seconds), flags.out);
  return kExitSuccess;
}

}  // namespace

SubcommandRunner SetupMapCommand(CLI::App* command) {
  auto flags = std::make_shared<MapFlags>();
  command->add_option("dataset", flags->dataset, "Dataset folder, manifest, or image folder")
      ->required();
  command->add_option("--out", flags->out, "Run directory to write")->required();
  command->add_option("--config", flags->config, "YAML file of mapping options");
  command->add_option("--camera", flags->camera, "Calibration, for a plain image folder");
  command->add_option("--radius", flags->radius, "Pipe inner radius in metres")
      ->check(CLI::PositiveNumber);
  return [flags] { return RunMap(*flags); };
}

}  // namespace pipescope
