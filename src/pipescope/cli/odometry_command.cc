// `pipescope odometry`: visual odometry over a dataset, writing a run directory (GUIDE §4):
// trajectory.tum, mosaic.png, run.json and, with ground truth, metrics.json.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "pipescope/camera/camera_io.h"
#include "pipescope/cli/method_choice.h"
#include "pipescope/cli/run_flags.h"
#include "pipescope/cli/subcommand.h"
#include "pipescope/geometry/camera_mount.h"
#include "pipescope/io/dataset.h"
#include "pipescope/io/trajectory.h"
#include "pipescope/pipeline/dense_vo.h"
#include "pipescope/pipeline/dense_vo_config.h"
#include "pipescope/pipeline/ekf_vo.h"
#include "pipescope/pipeline/ekf_vo_config.h"
#include "pipescope/pipeline/sparse_vo.h"
#include "pipescope/pipeline/sparse_vo_config.h"
#include "pipescope/pipeline/sparse_vo_verdict.h"
#include "pipescope/pipeline/wall_distance_statement.h"
#include "pipescope/report/run_directory.h"
#include "pipescope/report/run_quality.h"
#include "pipescope/util/atomic_file.h"
#include "pipescope/util/error.h"

namespace pipescope {
namespace {

struct OdometryFlags : RunFlags {
  std::string method;
  std::string method_reason;  // set when --method was not given and the method was chosen
};

// run.json's method_choice when the method was chosen for the user.
void NoteMethodChoice(const OdometryFlags& flags, RunReport* report) {
  if (flags.method_reason.empty()) return;
  report->Extra("method_choice") = {{"method", flags.method}, {"reason", flags.method_reason}};
}

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
      entry["bridged"] = frame.bridged;
    }
    failed.push_back(std::move(entry));
  }
  return failed;
}

// run.json's wall_distance, and a warning when the run's scale rests on an assumed one.
void ReportWallDistance(const WallDistanceStatement& statement, const std::string& method,
                        RunReport* report) {
  report->Extra("wall_distance") = WallDistanceJson(statement);
  const std::string warning = WallDistanceWarning(statement, method);
  if (!warning.empty()) report->Warn(warning);
}

// metrics.json, when the dataset has ground truth.
void WriteMetricsIfGroundTruth(const DatasetManifest& manifest, const Trajectory& trajectory,
                               RunDirectory* run) {
  if (manifest.groundtruth_path.empty()) return;
  run->WriteMetrics(ReadTumTrajectory(manifest.groundtruth_path), trajectory,
                    manifest.groundtruth_path.string());
}

// Every --config key of the odometry methods with its default and help (--list-keys).
void ListKeys() {
  std::cout << "Keys of --config FILE for the dense methods (default, range, help):\n"
            << DenseVoOptionTable().ListKeys(DenseOdometerOptions{})
            << "\nKeys of --config FILE for --method sparse:\n"
            << SparseVoOptionTable().ListKeys(SparseVoOptions{})
            << "\nKeys of --config FILE for --method ekf:\n"
            << EkfVoOptionTable().ListKeys(EkfVoOptions{});
}

// 000 §5: sparse VO on the cylinder; writes key frames and the sparse point cloud as well.
int RunSparseOdometry(const OdometryFlags& flags) {
  DatasetManifest manifest = OpenRunDataset(flags);
  SparseVoOptions options;
  if (!flags.config.empty()) SparseVoOptionTable().ApplyYamlFile(flags.config, &options);
  const Camera camera = ReadCamera(manifest.camera_path);
  // 000 §5 looks at the wall through a perspective lens; a fisheye's wall is seen at grazing
  // angles the cylinder model of the key points does not hold for.
  RequireCameraView(camera, manifest.camera_path, 0.0, 80.0,
                    "--method sparse needs a wall-looking camera; a fisheye looking down the "
                    "pipe is for pipescope map");
  RunDirectory run(flags.out, "odometry", "sparse");
  run.SetDataset(manifest);
  run.SetWriteReport(!flags.no_report);

  const SparseVoResult result = RunSparseVo(manifest, camera, options);

  RunReport& report = run.report();
  NoteMethodChoice(flags, &report);
  report.SetOptions(SparseVoOptionTable().ToJson(options));
  report.SetCount("frames",
                  static_cast<long long>(result.frames.size() + result.skipped_frames.size()));
  report.SetCount("frames_localised", static_cast<long long>(result.trajectory.size()));
  report.SetCount("frames_unreadable", static_cast<long long>(result.skipped_frames.size()));
  const long long failed = static_cast<long long>(result.frames.size()) -
                           static_cast<long long>(result.trajectory.size());
  report.SetCount("frames_failed", failed);
  report.SetCount("key_frames", static_cast<long long>(result.key_frames.size()));
  report.SetCount("points", static_cast<long long>(result.points.size()));
  report.SetCount("refinements", result.summary.refinements);
  report.SetCount("window_adjustments", result.summary.window_adjustments);
  report.SetCount("revisits", result.summary.revisits);
  report.SetCount("restarts", result.summary.restarts);
  if (result.summary.restarts > 0) {
    report.Warn(std::to_string(result.summary.restarts) +
                " time(s) the tracks were lost and the chain restarted at a pose predicted at "
                "the last measured speed: the distance across each gap is a prediction, not a "
                "measurement (restart_after_failed_frames)");
  }
  report.AddTiming("odometry", result.odometry_seconds);
  report.AddTiming("odometry_cpu", result.odometry_cpu_seconds);
  report.AddStageTimes("odometry", result.stage_times);
  report.AddTiming("mosaic", result.mosaic_seconds);
  report.AddTiming("mosaic_cpu", result.mosaic_cpu_seconds);
  report.Extra("failed_frames") = FailedFramesJson(result.frames);
  report.Extra("unreadable_frames") = result.skipped_frames;
  ReportWallDistance(result.wall_distance, "sparse", &report);
  report.Extra("initial_position") = {
      {"start_c_xy_m", {result.summary.initial_c_xy.x(), result.summary.initial_c_xy.y()}},
      {"optimised_c_xy_m", {result.summary.optimised_c_xy.x(), result.summary.optimised_c_xy.y()}},
      {"reprojection_rms_before_px", result.summary.initial_reprojection_rms_px},
      {"reprojection_rms_after_px", result.summary.optimised_reprojection_rms_px}};
  report.Extra("global_scale") = {
      {"offset_xy_m",
       {result.summary.global_scale.offset_xy.x(), result.summary.global_scale.offset_xy.y()}},
      {"scale", result.summary.global_scale.scale},
      {"residuals", result.summary.global_scale.residuals},
      {"reprojection_rms_before_px", result.summary.global_scale.initial_rms_px},
      {"reprojection_rms_after_px", result.summary.global_scale.final_rms_px}};
  nlohmann::json key_frames = nlohmann::json::array();
  for (const SparseKeyFrameRecord& key : result.summary.key_frame_records) {
    key_frames.push_back(
        {{"frame", key.frame_index}, {"keypoints", key.keypoints}, {"tracked", key.tracked}});
  }
  report.Extra("key_frames") = key_frames;
  if (failed > 0) {
    report.Warn(std::to_string(failed) +
                " frames could not be localised and have no pose (see failed_frames)");
  }
  if (result.points.empty()) {
    throw RunFailedError("no point of the wall was triangulated, so the path is not measured");
  }
  std::vector<FrameState> states;
  for (const SparseFrameRecord& frame : result.frames) {
    states.push_back(!frame.failure.empty() ? FrameState::kNotLocalised
                     : frame.predicted      ? FrameState::kPredicted
                                            : FrameState::kMeasured);
  }
  states.insert(states.end(), result.skipped_frames.size(), FrameState::kNotLocalised);
  report.Extra("cross_section_excursion_m") = result.cross_section_excursion_m;
  // What the window adjustments used, where `options` gives what was configured.
  report.Extra("cross_section_anchor_sigma_m") = result.cross_section_anchor_sigma_m;
  run.SetQuality(states, SparseVoVerdictReasons(result, options, *manifest.inner_radius_m));
  run.WriteTrajectory(result.trajectory);
  run.WriteKeyFrames(result.key_frames);
  run.WriteSparsePoints(result.points);
  run.WriteMosaic(result.mosaic, "unrolled", result.mosaic_pixel_m, result.mosaic_origin_m);
  WriteMetricsIfGroundTruth(manifest, result.trajectory, &run);
  run.Commit();
  spdlog::info(
      "sparse: {} frames localised ({} key frames) in {:.1f} s ({:.1f} frames/s); wrote {}",
      result.trajectory.size(), result.key_frames.size(), result.odometry_seconds,
      result.frames.size() / std::max(1e-9, result.odometry_seconds), flags.out);
  return kExitSuccess;
}

// run.json's `sections` of an ekf run: the geometry in the run's frame and where each lies along
// the centreline.
nlohmann::json EkfSectionsJson(const EkfVoResult& result) {
  nlohmann::json sections = nlohmann::json::array();
  for (std::size_t i = 0; i < result.sections.size(); ++i) {
    const EkfSectionRecord& section = result.sections[i];
    const Eigen::Vector3d& start = section.geometry.start;
    const Eigen::Vector3d& axis = section.geometry.axis;
    const double length = section.end_arc_m - section.start_arc_m;
    const Eigen::Vector3d centre = section.geometry.CentrelinePoint(0.5 * length);
    const Eigen::Vector3d end_axis = section.geometry.TangentAt(length);
    sections.push_back({{"index", i},
                        {"centre_m", {centre.x(), centre.y(), centre.z()}},
                        {"start_m", {start.x(), start.y(), start.z()}},
                        {"axis", {axis.x(), axis.y(), axis.z()}},
                        {"radius_m", section.geometry.Radius()},
                        {"curvature_per_m", section.geometry.curvature.norm()},
                        {"end_axis", {end_axis.x(), end_axis.y(), end_axis.z()}},
                        {"start_along_m", section.start_arc_m},
                        {"end_along_m", section.end_arc_m},
                        {"first_frame", section.first_frame},
                        {"reason", section.reason}});
  }
  return sections;
}

// Innovation statistics over the updated frames: median and worst of the per-frame figures.
nlohmann::json EkfInnovationJson(const EkfVoResult& result) {
  std::vector<double> rms, nis, used, gated_share;
  for (const EkfFrameRecord& frame : result.frames) {
    if (!frame.update.updated) continue;
    rms.push_back(frame.update.rms_innovation_px);
    nis.push_back(frame.update.mean_nis);
    used.push_back(frame.update.used);
    const int considered = frame.update.used + frame.update.gated;
    gated_share.push_back(considered > 0 ? double(frame.update.gated) / considered : 0.0);
  }
  auto median = [](std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
  };
  auto worst = [](const std::vector<double>& v) {
    return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end());
  };
  auto fewest = [](const std::vector<double>& v) {
    return v.empty() ? 0.0 : *std::min_element(v.begin(), v.end());
  };
  return {{"updated_frames", rms.size()},
          {"rms_px_median", median(rms)},
          {"rms_px_max", worst(rms)},
          {"mean_nis_median", median(nis)},
          {"mean_nis_max", worst(nis)},
          {"features_used_median", median(used)},
          {"features_used_min", fewest(used)},
          {"gated_share_median", median(gated_share)},
          {"gated_share_max", worst(gated_share)}};
}

// Largest relative disagreement between a section's fitted radius and the dataset's before the
// run is called unreliable: three sigmas of the 1 % prior every section has. On tube-bend and the
// straight set-ups the worst section is within 2.3 % (docs/ekf.md).
constexpr double kEkfMaxRadiusDisagreement = 0.03;
// Where a wall camera's view cannot measure its distance to the wall, an ekf run whose camera
// strays more than this share of that distance across the pipe is unreliable, as a sparse run
// is (SparseVoOptions::max_unobserved_excursion): on the 16-inch pipe's 25-degree view the
// filter followed a 9.7 mm wander to within 0.02-0.53 % on five runs and ended 3.4 % off, calling
// itself reliable, on the sixth (docs/conditions.md).
constexpr double kEkfMaxUnobservedExcursion = 0.02;
// Median over the updated frames of the tracks' mean normalised innovation squared (posterior)
// above which the run is unreliable: twice the 2 a filter whose pixel_sigma describes its tracks
// expects. Tracks that disagree with the filter by more than their assumed noise (texture too weak
// or noisy to track, frames of plain noise) move the estimate where the images do not support it:
// on weak, noisy wall texture 10.2 (a run 6.2 % off), on frames of plain noise 18.5 (65 % off);
// the runs that held (wall cameras, eleven tube-bend runs) stayed within 0.30 (docs/conditions.md).
constexpr double kEkfMaxMedianNis = 4.0;
// Turning of the chain (the bending sections' own turns and the angles between consecutive
// sections) above which the run's positions are unconfirmed: nothing in the filter checks the
// angle it turned. With straight sections only it came out 2-10 % short on simulated bends
// (docs/ekf.md); 10 % of 10 degrees moves the end of a run by at most 1.7 % of the path after the
// bend, so below this no turn error can reach the 2 % a reliable run promises.
constexpr double kEkfMaxUnconfirmedTurnDeg = 10.0;

double ChainTurnDeg(const std::vector<EkfSectionRecord>& sections) {
  double turn = 0.0;
  for (std::size_t i = 0; i < sections.size(); ++i) {
    const TubeSection& section = sections[i].geometry;
    const double length = sections[i].end_arc_m - sections[i].start_arc_m;
    // A bending section turns by its curvature times its length.
    turn += section.curvature.norm() * length;
    if (i + 1 == sections.size()) break;
    // An axis is a line: a section started on the way back of an out-and-back run points back
    // along the same tube, which is no turn.
    const double cosine = std::abs(section.TangentAt(length).dot(sections[i + 1].geometry.axis));
    turn += std::acos(std::min(cosine, 1.0));
  }
  return turn * 180.0 / M_PI;
}

std::string FormatPercent(double fraction) {
  char text[32];
  std::snprintf(text, sizeof(text), "%+.1f %%", 100.0 * fraction);
  return text;
}

// 004: the tubular EKF; writes the sections, the centreline and the dewarped mosaic as well.
int RunEkfOdometry(const OdometryFlags& flags) {
  DatasetManifest manifest = OpenRunDataset(flags);
  EkfVoOptions options;
  if (!flags.config.empty()) EkfVoOptionTable().ApplyYamlFile(flags.config, &options);
  const Camera camera = ReadCamera(manifest.camera_path);
  RunDirectory run(flags.out, "odometry", "ekf");
  run.SetDataset(manifest);
  run.SetWriteReport(!flags.no_report);
  run.SetSurveyLine(SurveyLine::kTravelledPath);

  const EkfVoResult result = RunEkfVo(manifest, camera, options);

  RunReport& report = run.report();
  NoteMethodChoice(flags, &report);
  report.SetOptions(EkfVoOptionTable().ToJson(options));
  report.SetCount("frames",
                  static_cast<long long>(result.frames.size() + result.skipped_frames.size()));
  report.SetCount("frames_localised", static_cast<long long>(result.trajectory.size()));
  report.SetCount("frames_unreadable", static_cast<long long>(result.skipped_frames.size()));
  report.SetCount("sections", static_cast<long long>(result.sections.size()));
  report.AddTiming("odometry", result.odometry_seconds);
  report.AddTiming("odometry_cpu", result.odometry_cpu_seconds);
  report.AddStageTimes("odometry", result.stage_times);
  report.AddTiming("mosaic", result.mosaic_seconds);
  report.Extra("failed_frames") = FailedFramesJson(result.frames);
  report.Extra("unreadable_frames") = result.skipped_frames;
  report.Extra("sections") = EkfSectionsJson(result);
  const nlohmann::json innovation = EkfInnovationJson(result);
  report.Extra("innovation") = innovation;
  report.Extra("centreline_length_m") = result.centreline.Length();
  // The distance the camera travelled along the tube: its last foot on the centreline from its
  // first.
  report.Extra("distance_along_centreline_m") =
      result.frame_arc_m.empty() ? 0.0 : result.frame_arc_m.back() - result.frame_arc_m.front();
  report.Extra("scale") =
      result.metric ? "metric: the first section's radius has the dataset's radius as its prior"
                    : "up to scale: the first section's radius is 1";
  if (!result.metric) {
    report.Warn("the run is up to scale (metric: false); distances are in units of the radius");
  }
  report.Extra("axis_along_tube") = result.axis_along_tube;
  report.Extra("chosen_by_the_view") = {
      {"curvature_sigma_radii", result.chosen.curvature_sigma_radii},
      {"spawn_lookahead_radii", result.chosen.spawn_lookahead_radii},
      {"flat_field_sigma_px", result.chosen.flat_field_sigma_px}};
  if (result.travel) {
    const TravelDirection& travel = *result.travel;
    report.Extra("travel_direction") = {
        {"found", travel.found},
        {"direction_in_camera", {travel.direction.x(), travel.direction.y(), travel.direction.z()}},
        {"reference_frame", travel.reference_frame},
        {"frame", travel.frame},
        {"inliers", travel.inliers},
        {"failure", travel.failure}};
    if (!travel.found) {
      report.Warn("axis_along_tube auto: the direction of travel could not be measured (" +
                  travel.failure +
                  "): the tube was taken to run along the optical axis (z); give "
                  "axis_along_tube in a --config");
    }
  }
  // A wall camera (the tube across the optical axis): what it knows of its distance to the wall.
  std::optional<WallDistanceStatement> wall_distance;
  if (!LooksDownTube(result.axis_in_camera) && result.metric && manifest.inner_radius_m) {
    const double radius = *manifest.inner_radius_m;
    const bool has_reference_scale =
        manifest.reference_scale_px_per_m && *manifest.reference_scale_px_per_m > 0.0;
    // The mount nearest the axis the filter started with.
    const std::string mount =
        std::abs(result.axis_in_camera.y()) > std::abs(result.axis_in_camera.x()) ? "y" : "x";
    wall_distance = MakeWallDistanceStatement(
        camera, CameraMount{mount}, radius, NominalStartWallDistance(manifest, camera, radius),
        has_reference_scale ? "reference_scale_px_per_m (estimated from the start on)"
                            : "none given: estimated from the start on",
        true);
    ReportWallDistance(*wall_distance, "ekf", &report);
  }
  std::vector<FrameState> states;
  for (const EkfFrameRecord& frame : result.frames) {
    if (frame.failure == "saturated") {
      states.push_back(FrameState::kNotLocalised);
    } else {
      states.push_back(frame.failure.empty() ? FrameState::kMeasured : FrameState::kPredicted);
    }
  }
  states.insert(states.end(), result.skipped_frames.size(), FrameState::kNotLocalised);
  // A section whose fitted radius leaves the dataset's is a section the chain of straight
  // cylinders did not explain (a bend followed too coarsely, a misplaced junction): the distance
  // through it is off by about as much (docs/ekf.md).
  std::vector<std::string> model_reasons;
  if (result.metric && manifest.inner_radius_m) {
    int off_sections = 0, worst = 0;
    double worst_off = 0.0;
    for (std::size_t i = 0; i < result.sections.size(); ++i) {
      const double off = result.sections[i].geometry.Radius() / *manifest.inner_radius_m - 1.0;
      if (std::abs(off) > kEkfMaxRadiusDisagreement) ++off_sections;
      if (std::abs(off) > std::abs(worst_off)) {
        worst_off = off;
        worst = static_cast<int>(i);
      }
    }
    if (off_sections > 0) {
      model_reasons.push_back(
          std::to_string(off_sections) + " of " + std::to_string(result.sections.size()) +
          " sections have a fitted radius more than " + FormatPercent(kEkfMaxRadiusDisagreement) +
          " off the dataset's (worst: section " + std::to_string(worst) + ", " +
          FormatPercent(worst_off) + "): the tube model does not explain the images there");
    }
  }
  if (wall_distance && !result.trajectory.empty()) {
    const double excursion = CrossSectionExcursion(result.trajectory);
    report.Extra("cross_section_excursion_m") = excursion;
    const std::string unobserved =
        UnobservedExcursionReason(*wall_distance, excursion, kEkfMaxUnobservedExcursion);
    if (!unobserved.empty()) model_reasons.push_back(unobserved);
  }
  const double median_nis = innovation["mean_nis_median"].get<double>();
  if (median_nis > kEkfMaxMedianNis) {
    model_reasons.push_back(fmt::format(
        "the tracks disagree with the filter: their innovations are a median {:.1f} times the "
        "variance its pixel_sigma ({:.2f} px) allows (limit {:.0f}; {:.2f} px rms): texture too "
        "weak or noisy to track",
        median_nis / 2.0, options.filter.pixel_sigma, kEkfMaxMedianNis / 2.0,
        innovation["rms_px_median"].get<double>()));
  }
  // Not observable from inside the filter: the positions beyond a bend are unconfirmed, while the
  // distance along the centreline, which the angle does not move, keeps its own verdict.
  std::vector<std::string> position_reasons;
  const double turn_deg = ChainTurnDeg(result.sections);
  if (turn_deg > kEkfMaxUnconfirmedTurnDeg) {
    position_reasons.push_back(fmt::format(
        "the sections turn {:.0f} deg in all: the filter cannot check the angle it turned (on "
        "simulated bends of good texture it came out within 1.5 deg, 11 deg off on weak texture "
        "through a fisheye, 16 deg where the bend was in view from the first frame, docs/ekf.md), "
        "so the positions beyond the bend and straight-line distances "
        "across it are unconfirmed; the distances along the centreline are not affected",
        turn_deg));
  }
  run.SetQuality(states, model_reasons, RunQualityLimits{}, position_reasons);
  run.WriteTrajectory(result.trajectory);
  // Not "unrolled": that names a straight pipe's (h, r phi) map, which the report lays on one
  // cylinder.
  run.WriteMosaic(result.mosaic, "tube-unrolled", result.mosaic_pixel_m,
                  cv::Point2d(result.mosaic_begin_m, 0.0));
  WriteCentrelineCsv(run.staging_path() / "centreline.csv", result.centreline);
  WriteCentrelinePly(run.staging_path() / "centreline.ply", result.centreline);
  WriteMetricsIfGroundTruth(manifest, result.trajectory, &run);
  run.Commit();
  spdlog::info(
      "ekf: {} frames localised, {} sections, centreline {:.3f} m, in {:.1f} s "
      "({:.1f} frames/s); wrote {}",
      result.trajectory.size(), result.sections.size(), result.centreline.Length(),
      result.odometry_seconds, result.frames.size() / std::max(1e-9, result.odometry_seconds),
      flags.out);
  return kExitSuccess;
}

int RunOdometry(const OdometryFlags& flags) {
  if (flags.list_keys) {
    ListKeys();
    return kExitSuccess;
  }
  if (flags.method.empty()) {
    const DatasetManifest manifest = OpenRunDataset(flags);
    const MethodChoice choice = ChooseOdometryMethod(manifest, ReadCamera(manifest.camera_path));
    spdlog::info("--method not given: {}, because {}", choice.method, choice.reason);
    OdometryFlags chosen = flags;
    chosen.method = choice.method;
    chosen.method_reason = choice.reason;
    // A --config names one method's keys, so only a run without one can fall back.
    if (choice.fallback.empty() || !flags.config.empty()) return RunOdometry(chosen);
    std::string why;
    try {
      const int status = RunOdometry(chosen);
      if (status != kExitSuccess) return status;
      const nlohmann::json report =
          nlohmann::json::parse(ReadTextFile(std::filesystem::path(flags.out) / "run.json"));
      // The fallbacks measure distance along a straight pipe only: positions across a bend the
      // first method could not confirm are no reason to prefer them.
      const std::vector<std::string> reasons = AlongPipeReasons(report["quality"]);
      if (reasons.empty()) return status;
      for (const std::string& reason : reasons) why += (why.empty() ? "" : "; ") + reason;
    } catch (const RunFailedError& error) {
      why = error.what();
    }
    spdlog::warn("{} was unreliable ({}): running {} instead", choice.method, why, choice.fallback);
    OdometryFlags fallback = flags;
    fallback.method = choice.fallback;
    fallback.method_reason = choice.reason + "; " + choice.method +
                             " was tried first and was unreliable (" + why + "), so " +
                             choice.fallback + " instead";
    return RunOdometry(fallback);
  }
  if (flags.method == "sparse") return RunSparseOdometry(flags);
  if (flags.method == "ekf") return RunEkfOdometry(flags);
  const std::vector<std::string> dense = DenseMethodNames();
  if (std::find(dense.begin(), dense.end(), flags.method) == dense.end()) {
    std::string valid;
    for (const std::string& name : dense) valid += name + ", ";
    throw InputError("--method: unknown method '" + flags.method + "' (valid: " + valid +
                     "sparse, ekf)");
  }
  DatasetManifest manifest = OpenRunDataset(flags);
  DenseOdometerOptions options;
  options.method = ParseDenseMethod(flags.method);
  if (!flags.config.empty()) DenseVoOptionTable().ApplyYamlFile(flags.config, &options);
  const Camera camera = ReadCamera(manifest.camera_path);
  RunDirectory run(flags.out, "odometry", DenseMethodName(options.method));
  run.SetDataset(manifest);
  run.SetWriteReport(!flags.no_report);

  const DenseVoResult result = RunDenseVo(manifest, camera, options);

  RunReport& report = run.report();
  NoteMethodChoice(flags, &report);
  nlohmann::json options_json = DenseVoOptionTable().ToJson(options);
  options_json["method"] = DenseMethodName(options.method);
  report.SetOptions(options_json);
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
  if (!result.cross_section_warning.empty()) report.Warn(result.cross_section_warning);
  if (result.cross_section_alignments + result.cross_section_rejections > 0) {
    report.SetCount("key_frames_cross_section_measured", result.cross_section_alignments);
    report.SetCount("key_frames_cross_section_rejected", result.cross_section_rejections);
    report.SetCount("key_frames_cross_section_faint", result.cross_section_faint);
    report.Extra("cross_section_blurred_from_key_frame") =
        result.cross_section_blurred_from >= 0 ? nlohmann::json(result.cross_section_blurred_from)
                                               : nlohmann::json(nullptr);
    if (result.cross_section_blurred_from >= 0 && result.cross_section_warning.empty()) {
      report.Warn(fmt::format(
          "dense-unrolled: the wall was too faint to align at full detail; from key frame {} the "
          "camera's place was measured on frames blurred by {:g} px, less surely "
          "(cross_section_sigma_mm in run.json)",
          result.cross_section_blurred_from, options.cross_section_faint_smooth_px));
    }
    std::vector<double> sigmas = result.cross_section_sigmas_m;
    if (!sigmas.empty()) {
      std::sort(sigmas.begin(), sigmas.end());
      report.Extra("cross_section_sigma_mm") = {
          {"median", 1000.0 * sigmas[sigmas.size() / 2]},
          {"p90", 1000.0 * sigmas[sigmas.size() * 9 / 10]}};
    }
  }
  report.AddTiming("odometry", result.registration_seconds);
  report.AddStageTimes("odometry", result.stage_times);
  report.AddTiming("odometry_loop_cpu", result.loop_cpu_seconds);
  report.Extra("failed_frames") = FailedFramesJson(result.frames);
  report.Extra("unreadable_frames") = result.skipped_frames;
  ReportWallDistance(result.wall_distance, DenseMethodName(options.method), &report);
  report.Extra("integer_only_frames") = integer_only;
  if (!integer_only.empty()) {
    report.Warn(std::to_string(integer_only.size()) +
                " frame pairs kept the full search's whole-pixel shift: the Gauss-Newton "
                "refinement did not converge or moved too far (see integer_only_frames)");
  }
  if (result.failed_pairs > 0) {
    long long bridged = 0;
    for (const DenseFrameRecord& frame : result.frames) bridged += frame.bridged ? 1 : 0;
    report.Warn(std::to_string(result.failed_pairs) + " frame pairs failed to register; " +
                std::to_string(bridged) +
                " of them were bridged between the measured frames around them, the others "
                "predicted at constant velocity (see failed_frames)");
  }

  std::vector<FrameState> states;
  for (const DenseFrameRecord& frame : result.frames) {
    states.push_back(frame.failure.empty() ? FrameState::kMeasured
                     : frame.bridged       ? FrameState::kBridged
                                           : FrameState::kPredicted);
  }
  states.insert(states.end(), result.skipped_frames.size(), FrameState::kNotLocalised);
  run.SetQuality(states);
  run.WriteTrajectory(result.trajectory);
  run.WriteMosaic(result.mosaic, options.method == DenseMethod::kUnrolled ? "unrolled" : "image",
                  result.mosaic_pixel_m, result.mosaic_origin_m);
  WriteMetricsIfGroundTruth(manifest, result.trajectory, &run);
  run.Commit();
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
  AddRunFlags(command, flags.get(), "YAML file of method options (see --list-keys)");
  std::string methods;
  for (const std::string& name : DenseMethodNames())
    methods += (methods.empty() ? "" : " | ") + name;
  methods += " | sparse | ekf";
  command->add_option("--method", flags->method,
                      "Odometry method: " + methods +
                          " (default: chosen for the camera and pipe, docs/conditions.md)");
  return [flags] { return RunOdometry(*flags); };
}

}  // namespace pipescope
