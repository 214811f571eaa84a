// `pipescope odometry`: visual odometry over a dataset, writing a run directory (GUIDE §4):
// trajectory.tum, mosaic.png, run.json and, with ground truth, metrics.json.
#include <spdlog/spdlog.h>

#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <type_traits>
#include <vector>

#include "pipescope/camera/camera_io.h"
#include "pipescope/cli/subcommand.h"
#include "pipescope/eval/metrics_report.h"
#include "pipescope/eval/trajectory_metrics.h"
#include "pipescope/io/dataset.h"
#include "pipescope/io/point_cloud_ply.h"
#include "pipescope/io/trajectory.h"
#include "pipescope/mapping/mosaic_io.h"
#include "pipescope/pipeline/dense_vo.h"
#include "pipescope/pipeline/dense_vo_config.h"
#include "pipescope/pipeline/sparse_vo.h"
#include "pipescope/pipeline/sparse_vo_config.h"
#include "pipescope/util/atomic_file.h"
#include "pipescope/util/error.h"
#include "pipescope/util/run_report.h"
#include "pipescope/util/staging_directory.h"
#include "pipescope/util/timer.h"

namespace pipescope {
namespace {

struct OdometryFlags {
  std::string dataset;
  std::string method;
  std::string out;
  std::string config;
  std::string camera;
  std::optional<double> radius;
};

// The frames a method could not use, with the reason (dense and sparse frame records).
template <typename FrameRecord>
nlohmann::json FailedFramesJson(const std::vector<FrameRecord>& frames) {
  nlohmann::json failed = nlohmann::json::array();
  for (const FrameRecord& frame : frames) {
    if (frame.failure.empty()) continue;
    nlohmann::json entry = {{"index", frame.index},
                            {"name", frame.name},
                            {"timestamp", frame.timestamp},
                            {"reason", frame.failure}};
    if constexpr (std::is_same_v<FrameRecord, DenseFrameRecord>) {
      entry["predicted_shift_px"] = {frame.shift.x, frame.shift.y};
    }
    failed.push_back(std::move(entry));
  }
  return failed;
}

// mosaic.png and its description in run.json, when a mosaic was built; pixel_m 0: the
// image-space map, which has no metric cell size.
void WriteMosaic(const cv::Mat& mosaic, const char* kind, double pixel_m, cv::Point2d origin_m,
                 const std::filesystem::path& dir, RunReport* report) {
  if (mosaic.empty()) return;
  WriteMosaicPng(dir / "mosaic.png", mosaic);
  report->Extra("mosaic") = {
      {"kind", kind},
      {"width_px", mosaic.cols},
      {"height_px", mosaic.rows},
      {"pixel_m", pixel_m > 0.0 ? nlohmann::json(pixel_m) : nlohmann::json(nullptr)},
      {"origin_h_m", origin_m.x},
      {"origin_s_m", origin_m.y}};
}

void WriteMetrics(const DatasetManifest& manifest, const Trajectory& trajectory,
                  const std::filesystem::path& folder) {
  if (manifest.groundtruth_path.empty()) return;
  const Metrics metrics =
      EvaluateTrajectory(ReadTumTrajectory(manifest.groundtruth_path), trajectory, {});
  WriteTextFileAtomically(folder / "metrics.json", MetricsToJson(metrics).dump(2) + "\n");
  std::cout << MetricsToTable(metrics);
}

// 000 §5: sparse VO on the cylinder; writes key frames and the sparse point cloud as well.
int RunSparseOdometry(const OdometryFlags& flags) {
  const Timer total;
  DatasetManifest manifest = OpenDataset(
      flags.dataset, {.camera_path = flags.camera, .inner_radius_m = flags.radius, .fps = {}});
  SparseVoOptions options;
  if (!flags.config.empty()) ApplySparseVoConfig(flags.config, &options);
  const Camera camera = ReadCamera(manifest.camera_path);
  StagingDirectory staging(flags.out, "--out", "run.json");

  const SparseVoResult result = RunSparseVo(manifest, camera, options);

  RunReport report("odometry");
  report.SetMethod("sparse");
  report.SetOptions(SparseVoOptionsToJson(options));
  report.SetCount("frames",
                  static_cast<long long>(result.frames.size() + result.skipped_frames.size()));
  report.SetCount("frames_localised", static_cast<long long>(result.trajectory.size()));
  report.SetCount("frames_unreadable", static_cast<long long>(result.skipped_frames.size()));
  const long long failed = static_cast<long long>(result.frames.size()) -
                           static_cast<long long>(result.trajectory.size());
  report.SetCount("frames_failed", failed);
  report.SetCount("key_frames", static_cast<long long>(result.key_frames.size()));
  report.SetCount("points", static_cast<long long>(result.points.size()));
  report.SetCount("refinements", result.refinements);
  report.SetCount("window_adjustments", result.window_adjustments);
  report.SetCount("revisits", result.revisits);
  report.AddTiming("odometry", result.odometry_seconds);
  report.AddTiming("odometry_cpu", result.odometry_cpu_seconds);
  for (const auto& [stage, seconds] : result.stage_seconds) {
    report.AddTiming("odometry_" + stage, seconds);
  }
  for (const auto& [stage, seconds] : result.stage_cpu_seconds) {
    report.AddTiming("odometry_" + stage + "_cpu", seconds);
  }
  report.AddTiming("mosaic", result.mosaic_seconds);
  report.AddTiming("mosaic_cpu", result.mosaic_cpu_seconds);
  report.Extra("failed_frames") = FailedFramesJson(result.frames);
  report.Extra("unreadable_frames") = result.skipped_frames;
  report.Extra("initial_position") = {
      {"start_c_xy_m", {result.initial_c_xy.x(), result.initial_c_xy.y()}},
      {"optimised_c_xy_m", {result.optimised_c_xy.x(), result.optimised_c_xy.y()}},
      {"reprojection_rms_before_px", result.initial_reprojection_rms_px},
      {"reprojection_rms_after_px", result.optimised_reprojection_rms_px}};
  report.Extra("global_scale") = {
      {"offset_xy_m", {result.global_scale.offset_xy.x(), result.global_scale.offset_xy.y()}},
      {"scale", result.global_scale.scale},
      {"residuals", result.global_scale.residuals},
      {"reprojection_rms_before_px", result.global_scale.initial_rms_px},
      {"reprojection_rms_after_px", result.global_scale.final_rms_px}};
  nlohmann::json key_frames = nlohmann::json::array();
  for (const SparseKeyFrameRecord& key : result.key_frame_records) {
    key_frames.push_back(
        {{"frame", key.frame_index}, {"keypoints", key.keypoints}, {"tracked", key.tracked}});
  }
  report.Extra("key_frames") = key_frames;
  if (failed > 0) {
    report.Warn(std::to_string(failed) +
                " frames could not be localised and have no pose (see failed_frames)");
  }
  WriteTumTrajectory(staging.path() / "trajectory.tum", result.trajectory);
  WriteTumTrajectory(staging.path() / "keyframes.tum", result.key_frames);
  WritePlyPoints(staging.path() / "points_sparse.ply", result.points);
  WriteMosaic(result.mosaic, "unrolled", result.mosaic_pixel_m, result.mosaic_origin_m,
              staging.path(), &report);
  WriteMetrics(manifest, result.trajectory, staging.path());
  report.AddTiming("total", total.ElapsedSeconds());
  report.Write(staging.path() / "run.json");
  staging.Commit();
  spdlog::info(
      "sparse: {} frames localised ({} key frames) in {:.1f} s ({:.1f} frames/s); wrote {}",
      result.trajectory.size(), result.key_frames.size(), result.odometry_seconds,
      result.frames.size() / std::max(1e-9, result.odometry_seconds), flags.out);
  return kExitSuccess;
}

int RunOdometry(const OdometryFlags& flags) {
  if (flags.method == "sparse") return RunSparseOdometry(flags);
  const Timer total;
  DatasetManifest manifest = OpenDataset(
      flags.dataset, {.camera_path = flags.camera, .inner_radius_m = flags.radius, .fps = {}});
  DenseVoOptions options;
  options.method = ParseDenseMethod(flags.method);
  if (!flags.config.empty()) ApplyDenseVoConfig(flags.config, &options);
  const Camera camera = ReadCamera(manifest.camera_path);
  StagingDirectory staging(flags.out, "--out", "run.json");

  const DenseVoResult result = RunDenseVo(manifest, camera, options);

  RunReport report("odometry");
  report.SetMethod(DenseMethodName(options.method));
  report.SetOptions(DenseVoOptionsToJson(options));
  report.SetCount("frames",
                  static_cast<long long>(result.frames.size() + result.skipped_frames.size()));
  report.SetCount("frames_localised", static_cast<long long>(result.trajectory.size()));
  report.SetCount("frames_unreadable", static_cast<long long>(result.skipped_frames.size()));
  report.SetCount("pairs_failed", result.failed_pairs);
  long long still = 0;
  for (const DenseFrameRecord& frame : result.frames) still += frame.still ? 1 : 0;
  report.SetCount("pairs_still", still);
  // dense-hybrid's pairs whose sub-pixel refinement was not used: reported, not hidden.
  nlohmann::json integer_only = nlohmann::json::array();
  for (const DenseFrameRecord& frame : result.frames) {
    if (frame.integer_only) integer_only.push_back(frame.index);
  }
  report.SetCount("pairs_integer_only", static_cast<long long>(integer_only.size()));
  long long key_frames = 0;
  for (const DenseFrameRecord& frame : result.frames) key_frames += frame.key_frame ? 1 : 0;
  report.SetCount("key_frames", key_frames);
  report.AddTiming("odometry", result.registration_seconds);
  report.AddTiming("odometry_reading", result.reading_seconds);
  report.AddTiming("odometry_preparing", result.preparing_seconds);
  report.AddTiming("odometry_registering", result.registering_seconds);
  report.AddTiming("odometry_loop_cpu", result.loop_cpu_seconds);
  report.Extra("failed_frames") = FailedFramesJson(result.frames);
  report.Extra("unreadable_frames") = result.skipped_frames;
  report.Extra("integer_only_frames") = integer_only;
  if (!integer_only.empty()) {
    report.Warn(std::to_string(integer_only.size()) +
                " frame pairs kept the full search's whole-pixel shift: the Gauss-Newton "
                "refinement did not converge or moved too far (see integer_only_frames)");
  }
  if (result.failed_pairs > 0) {
    report.Warn(std::to_string(result.failed_pairs) +
                " frame pairs failed to register; their motion was predicted at constant "
                "velocity (see failed_frames)");
  }

  WriteTumTrajectory(staging.path() / "trajectory.tum", result.trajectory);
  WriteMosaic(result.mosaic, options.method == DenseMethod::kUnrolled ? "unrolled" : "image",
              result.mosaic_pixel_m, result.mosaic_origin_m, staging.path(), &report);
  WriteMetrics(manifest, result.trajectory, staging.path());
  report.AddTiming("total", total.ElapsedSeconds());
  report.Write(staging.path() / "run.json");
  staging.Commit();
  spdlog::info("{}: {} frames localised in {:.1f} s ({:.1f} frames/s), {} failed pairs; wrote {}",
               DenseMethodName(options.method), result.trajectory.size(),
               result.registration_seconds,
               result.trajectory.size() / std::max(1e-9, result.registration_seconds),
               result.failed_pairs, flags.out);
  return kExitSuccess;
}

}  // namespace

SubcommandRunner SetupOdometryCommand(CLI::App* command) {
  auto flags = std::make_shared<OdometryFlags>();
  command->add_option("dataset", flags->dataset, "Dataset folder, manifest, or image folder")
      ->required();
  std::string methods;
  for (const std::string& name : DenseMethodNames())
    methods += (methods.empty() ? "" : " | ") + name;
  methods += " | sparse";
  command->add_option("--method", flags->method, "Odometry method: " + methods)->required();
  command->add_option("--out", flags->out, "Run directory to write")->required();
  command->add_option("--config", flags->config, "YAML file of method options");
  command->add_option("--camera", flags->camera, "Calibration, for a plain image folder");
  command->add_option("--radius", flags->radius, "Pipe inner radius in metres")
      ->check(CLI::PositiveNumber);
  return [flags] { return RunOdometry(*flags); };
}

}  // namespace pipescope
