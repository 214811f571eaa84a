// `pipescope odometry`: visual odometry over a dataset, writing a run directory (GUIDE §4):
// trajectory.tum, mosaic.png, run.json and, with ground truth, metrics.json.
#include <spdlog/spdlog.h>

#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "pipescope/camera/camera_io.h"
#include "pipescope/cli/subcommand.h"
#include "pipescope/eval/metrics_report.h"
#include "pipescope/eval/trajectory_metrics.h"
#include "pipescope/io/dataset.h"
#include "pipescope/io/trajectory.h"
#include "pipescope/mapping/mosaic_io.h"
#include "pipescope/pipeline/dense_vo.h"
#include "pipescope/pipeline/dense_vo_config.h"
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

nlohmann::json FailedFramesJson(const DenseVoResult& result) {
  nlohmann::json failed = nlohmann::json::array();
  for (const DenseFrameRecord& frame : result.frames) {
    if (frame.failure.empty()) continue;
    failed.push_back({{"index", frame.index},
                      {"name", frame.name},
                      {"timestamp", frame.timestamp},
                      {"reason", frame.failure},
                      {"predicted_shift_px", {frame.shift.x, frame.shift.y}}});
  }
  return failed;
}

int RunOdometry(const OdometryFlags& flags) {
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
  report.AddTiming("odometry", result.registration_seconds);
  report.AddTiming("odometry_reading", result.reading_seconds);
  report.AddTiming("odometry_preparing", result.preparing_seconds);
  report.AddTiming("odometry_registering", result.registering_seconds);
  report.AddTiming("odometry_loop_cpu", result.loop_cpu_seconds);
  report.Extra("failed_frames") = FailedFramesJson(result);
  report.Extra("unreadable_frames") = result.skipped_frames;
  if (result.failed_pairs > 0) {
    report.Warn(std::to_string(result.failed_pairs) +
                " frame pairs failed to register; their motion was predicted at constant "
                "velocity (see failed_frames)");
  }

  WriteTumTrajectory(staging.path() / "trajectory.tum", result.trajectory);
  if (!result.mosaic.empty()) {
    WriteMosaicPng(staging.path() / "mosaic.png", result.mosaic);
    report.Extra("mosaic") = {
        {"kind", options.method == DenseMethod::kUnrolled ? "unrolled" : "image"},
        {"width_px", result.mosaic.cols},
        {"height_px", result.mosaic.rows},
        {"pixel_m", result.mosaic_pixel_m > 0.0 ? nlohmann::json(result.mosaic_pixel_m)
                                                : nlohmann::json(nullptr)},
        {"origin_h_m", result.mosaic_origin_m.x},
        {"origin_s_m", result.mosaic_origin_m.y}};
  }
  if (!manifest.groundtruth_path.empty()) {
    const Metrics metrics =
        EvaluateTrajectory(ReadTumTrajectory(manifest.groundtruth_path), result.trajectory, {});
    WriteTextFileAtomically(staging.path() / "metrics.json", MetricsToJson(metrics).dump(2) + "\n");
    std::cout << MetricsToTable(metrics);
  }
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
  command->add_option("--method", flags->method, "Odometry method: " + methods)->required();
  command->add_option("--out", flags->out, "Run directory to write")->required();
  command->add_option("--config", flags->config, "YAML file of method options");
  command->add_option("--camera", flags->camera, "Calibration, for a plain image folder");
  command->add_option("--radius", flags->radius, "Pipe inner radius in metres")
      ->check(CLI::PositiveNumber);
  return [flags] { return RunOdometry(*flags); };
}

}  // namespace pipescope
