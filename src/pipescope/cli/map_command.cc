// `pipescope map`: fisheye pipe mapping (001 §III A-D), writing a run directory (GUIDE §4):
// trajectory.tum, keyframes.tum, points_sparse.ply, points_dense.ply and a dense mosaic per
// straight section, classification.png, junctions.yaml, run.json and, with ground truth,
// metrics.json.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "pipescope/camera/camera_io.h"
#include "pipescope/cli/run_flags.h"
#include "pipescope/cli/subcommand.h"
#include "pipescope/io/dataset.h"
#include "pipescope/io/junctions.h"
#include "pipescope/io/trajectory.h"
#include "pipescope/mapping/dense_appearance_ply.h"
#include "pipescope/pipeline/fisheye_mapping.h"
#include "pipescope/pipeline/fisheye_mapping_config.h"
#include "pipescope/pipeline/turn_confirmation.h"
#include "pipescope/pipeline/window_confirmation.h"
#include "pipescope/report/run_directory.h"
#include "pipescope/util/error.h"
#include "pipescope/util/timer.h"

namespace pipescope {
namespace {

// points_sparse.ply: one colour per section (straight sections in alternating blues and greens,
// T-intersections red).
void WriteSparsePly(const FisheyeMappingResult& result, RunDirectory* run) {
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
  run->WriteSparsePoints(positions, colours, "pipescope map: sparse points, coloured by section");
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
  const std::map<int, StraightSectionWindows> windows = CountStraightSectionWindows(result.windows);
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
    if (section.view_class == PipeViewClass::kStraight) {
      // How many of the section's windows confirmed its length (pipeline/window_confirmation.h).
      const auto counted = windows.find(static_cast<int>(s));
      entry["windows"] = counted == windows.end() ? 0 : counted->second.windows;
      entry["windows_rejected"] = counted == windows.end() ? 0 : counted->second.rejected;
    }
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

nlohmann::json Vector(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

// A rotation as its axis times its angle, in degrees.
nlohmann::json RotationVectorDeg(const Eigen::Matrix3d& rotation) {
  const Eigen::AngleAxisd angle_axis(rotation);
  return Vector(angle_axis.axis() * angle_axis.angle() * 180.0 / M_PI);
}

// run.json `loop_closure` (001 §III-E).
nlohmann::json LoopClosureJson(const LoopClosureRecord& record) {
  nlohmann::json passes = nlohmann::json::array();
  for (const SectionPass& pass : record.passes) {
    passes.push_back({{"plan_section", pass.section}, {"toward_end", pass.toward_end}});
  }
  nlohmann::json edges = nlohmann::json::array();
  for (const LoopEdgeRecord& edge : record.edges) {
    edges.push_back({{"earlier_keyframe", edge.earlier_keyframe},
                     {"later_keyframe", edge.later_keyframe},
                     {"path_m", edge.path_m},
                     {"matches", edge.matches},
                     {"inliers", edge.inliers},
                     {"rms_deg", edge.rms_deg},
                     {"runner_up_keyframe", edge.runner_up_keyframe},
                     {"runner_up_inliers", edge.runner_up_inliers},
                     {"accepted", edge.accepted},
                     {"rejection", edge.rejection},
                     {"translation_m", Vector(edge.earlier_from_later.translation())},
                     {"rotation_vector_deg", RotationVectorDeg(edge.earlier_from_later.linear())}});
  }
  nlohmann::json revisits = nlohmann::json::array();
  for (const JunctionRevisit& revisit : record.revisits) {
    revisits.push_back({{"junction", revisit.name},
                        {"t_sections", revisit.t_sections},
                        {"gap_before_m", revisit.gap_before_m},
                        {"gap_after_m", revisit.gap_after_m},
                        {"path_between_m", revisit.path_between_m},
                        {"gap_across_path_only", revisit.across_path_only}});
  }
  nlohmann::json turn_changes = nlohmann::json::array();
  for (const TTurnChange& change : record.t_turn_changes) {
    turn_changes.push_back(
        {{"section", change.section}, {"turn_change_deg", change.turn_change_deg}});
  }
  return {{"applied", record.applied},
          {"why_not", record.why_not},
          {"turns", record.turns},
          {"passes", passes},
          {"unmatched_reverse_passes", record.unmatched_reverse_passes},
          {"edges", edges},
          {"revisits", revisits},
          {"t_turn_changes", turn_changes},
          {"graph",
           {{"converged", record.graph.converged},
            {"initial_cost", record.graph.initial_cost},
            {"final_cost", record.graph.final_cost},
            {"iterations", record.graph.iterations}}}};
}

// run.json `t_intersections` (001 §III-D), and the junctions (named J1, J2, ... in the order
// passed) whose centre a model placed, for junctions.yaml.
nlohmann::json TIntersectionsJson(const FisheyeMappingResult& result,
                                  std::vector<Junction>* junctions) {
  nlohmann::json entries = nlohmann::json::array();
  for (const TIntersectionRecord& t : result.t_intersections) {
    nlohmann::json entry = {{"section", t.section},
                            {"red_keyframe", t.red_keyframe},
                            {"blue_keyframe", t.blue_keyframe},
                            {"adjusted", t.rejection.empty()},
                            {"rejection", t.rejection},
                            {"end_fit_points", {t.red_fit_points, t.blue_fit_points}},
                            {"end_fit_median_m", {t.red_fit_m, t.blue_fit_m}}};
    if (t.modelled) {
      Junction junction;
      junction.name = "J" + std::to_string(junctions->size() + 1);
      junction.timestamp = t.timestamp;
      junction.center = t.geometry.centre;
      junction.axes = {t.geometry.red_direction, t.geometry.blue_direction};
      junctions->push_back(junction);
      entry["junction"] = junction.name;
      entry["center"] = Vector(t.geometry.centre);
      entry["timestamp"] = t.timestamp;
      entry["red_axis"] = Vector(t.geometry.red_direction);
      entry["blue_axis"] = Vector(t.geometry.blue_direction);
      entry["phi_deg"] = t.model[kPhi] * 180.0 / M_PI;
      // "given": held at the user's fitting angle; "measured": the T model's own.
      entry["phi_source"] = t.phi_given ? "given" : "measured";
      entry["l_red_m"] = t.model[kLengthRed];
      entry["l_blue_m"] = t.model[kLengthBlue];
      entry["axis_gap_m"] = t.axis_gap_m;
      entry["initial"] = {{"phi_deg", t.initial_model[kPhi] * 180.0 / M_PI},
                          {"l_red_m", t.initial_model[kLengthRed]},
                          {"l_blue_m", t.initial_model[kLengthBlue]}};
    }
    if (t.triangulated_points > 0) {
      nlohmann::json starts = nlohmann::json::array();
      for (const TIntersectionRecord::StartScore& start : t.start_scores) {
        starts.push_back({{"stage", start.stage},
                          {"scale", start.scale},
                          {"phi_offset_deg", start.phi_offset_deg},
                          {"score", start.score},
                          {"phi_deg", start.phi_deg}});
      }
      entry["starts"] = starts;
      entry["start_scale"] = t.start_scale;
      entry["start_phi_offset_deg"] = t.start_phi_offset_deg;
      entry["phi_start_at_range_end"] = t.phi_start_at_range_end;
      entry["points"] = t.triangulated_points;
      entry["observations"] = t.summary.observations;
      entry["outliers_removed"] = t.summary.outliers_removed;
      entry["initial_rms_px"] = t.summary.initial_rms_px;
      entry["final_rms_px"] = t.summary.final_rms_px;
      entry["cylinder_rms_m"] = t.summary.cylinder_rms_m;
      entry["red_points"] = t.summary.red_points;
      entry["blue_points"] = t.summary.blue_points;
      entry["seconds"] = t.summary.seconds;
      entry["stage_iterations"] = t.summary.stage_iterations;
    }
    if (t.rejection.empty()) {
      entry["blue_shift_m"] = t.blue_shift_m;
      entry["blue_turn_deg"] = t.blue_turn_deg;
    }
    entries.push_back(entry);
  }
  return entries;
}

// The dense map as BuildDenseMap finishes its pieces: points_dense.ply is written piece by
// piece (a long route never holds all its points); each piece's grid, 8 bit with unseen cells
// black, is kept for its section's mosaic (the pieces' grids one after the other along the
// pipe, a T's red piece then its blue one), and run.json `dense_map` describes them.
class DenseMapWriter {
 public:
  explicit DenseMapWriter(const std::filesystem::path& ply_path)
      : ply_(ply_path, "pipescope map: dense appearance map (001 IV-B), metres, run frame") {}

  void Add(int index, const DenseMapPiece& piece) {
    ply_.Append(piece.map.points);
    Finished& finished = finished_[index];
    finished.grid = piece.map.mean_grey.clone();
    cv::patchNaNs(finished.grid, 0.0);
    finished.grid.convertTo(finished.grid, CV_8U);
    finished.cells_seen = static_cast<long long>(piece.map.points.size());
  }

  // The mosaics and run.json `dense_map`, once the pass has ended; closes the PLY.
  void Finish(const std::vector<DenseMapPiece>& all, const DenseMapPassOptions& options,
              RunDirectory* run) {
    ply_.Close();
    std::map<int, std::vector<cv::Mat>> section_grids;
    nlohmann::json pieces = nlohmann::json::array();
    for (std::size_t index = 0; index < all.size(); ++index) {
      const DenseMapPiece& piece = all[index];
      const Finished& finished = finished_[static_cast<int>(index)];
      section_grids[piece.section].push_back(finished.grid);
      const Eigen::Vector3d& p = piece.cylinder.axis_point;
      const Eigen::Vector3d& d = piece.cylinder.axis_direction;
      const Eigen::Vector3d r =
          piece.cylinder.reference_direction.value_or(Eigen::Vector3d::Zero());
      const char* part = piece.part == DenseMapPart::kStraight ? "straight"
                         : piece.part == DenseMapPart::kTRed   ? "t-red"
                                                               : "t-blue";
      pieces.push_back({{"section", piece.section},
                        {"part", part},
                        {"first_keyframe", piece.first_keyframe},
                        {"last_keyframe", piece.last_keyframe},
                        {"axis_point", {p.x(), p.y(), p.z()}},
                        {"axis_direction", {d.x(), d.y(), d.z()}},
                        {"reference_direction", {r.x(), r.y(), r.z()}},
                        {"begin_m", piece.cylinder.begin_m},
                        {"end_m", piece.cylinder.end_m},
                        {"rows", finished.grid.rows},
                        {"cols", finished.grid.cols},
                        {"cells_seen", finished.cells_seen},
                        {"keyframes_used", piece.keyframes_used},
                        {"fit_median_m", piece.fit_median_m}});
    }
    nlohmann::json mosaics = nlohmann::json::array();
    for (const auto& [section, grids] : section_grids) {
      cv::Mat mosaic;
      cv::vconcat(grids, mosaic);
      const std::string name = "dense_section_" + std::to_string(section) + ".png";
      run->WriteImage(name, mosaic);
      mosaics.push_back({{"section", section}, {"file", name}});
    }
    run->report().Extra("dense_map") = {{"spacing_m", options.appearance.spacing_m},
                                        {"points", ply_.points()},
                                        {"pieces", pieces},
                                        {"mosaics", mosaics}};
  }

 private:
  struct Finished {
    cv::Mat grid;
    long long cells_seen = 0;
  };
  DenseAppearancePlyWriter ply_;
  std::map<int, Finished> finished_;
};

int RunMap(const RunFlags& flags) {
  if (flags.list_keys) {
    std::cout << "Keys of --config FILE (default, range, help):\n"
              << FisheyeMappingOptionTable().ListKeys(FisheyeMappingOptions{});
    return kExitSuccess;
  }
  const Timer total;
  DatasetManifest manifest = OpenRunDataset(flags);
  FisheyeMappingOptions options;
  options.odometry.window.radius_m = RequireInnerRadius(manifest);
  if (!flags.config.empty()) FisheyeMappingOptionTable().ApplyYamlFile(flags.config, &options);
  const Camera camera = ReadCamera(manifest.camera_path);
  // 001 looks down the pipe through a fisheye: the wall all around, ahead and beside. A narrow
  // camera sees too little of it to track and gives a map of nothing.
  RequireCameraView(camera, manifest.camera_path, 60.0, 180.0,
                    "map needs a forward-looking wide-angle or fisheye camera; for a camera "
                    "looking at the wall, use pipescope odometry");
  std::optional<Trajectory> ground_truth;
  if (!manifest.groundtruth_path.empty())
    ground_truth = ReadTumTrajectory(manifest.groundtruth_path);
  RunDirectory run(flags.out, "map", "fisheye-sba-cylinder");
  run.SetDataset(manifest);
  run.SetWriteReport(!flags.no_report);

  std::optional<DenseMapWriter> dense_writer;
  DenseMapPieceSink dense_sink;
  if (options.dense_map.enabled) {
    dense_writer.emplace(run.staging_path() / "points_dense.ply");
    dense_sink = [&](int index, const DenseMapPiece& piece) { dense_writer->Add(index, piece); };
  }
  const FisheyeMappingResult result = RunFisheyeMapping(manifest, camera, options, dense_sink);
  if (result.keyframes.empty()) {
    throw InputError(flags.dataset + ": no frame could be used for mapping");
  }

  RunReport& report = run.report();
  nlohmann::json options_json = FisheyeMappingOptionTable().ToJson(options);
  options_json["radius_m"] = options.odometry.window.radius_m;
  report.SetOptions(options_json);
  report.SetCount("frames",
                  result.frames + static_cast<long long>(result.unreadable_frames.size()));
  report.SetCount("frames_localised", static_cast<long long>(result.trajectory.size()));
  report.SetCount("frames_unusable", static_cast<long long>(result.failed_frames.size()));
  report.SetCount("frames_unreadable", static_cast<long long>(result.unreadable_frames.size()));
  report.SetCount("keyframes", static_cast<long long>(result.keyframes.size()));
  report.SetCount("points_sparse", static_cast<long long>(result.points.size()));
  report.SetCount("tracking_resets", result.tracking_resets);
  report.AddStageTimes("", result.stage_times);
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
                              {"stationary", keyframe.stationary},
                              {"median_flow_px", keyframe.median_flow_px}});
  }
  report.Extra("keyframes") = classification;
  report.Extra("sections") = SectionsJson(result, ground_truth ? &*ground_truth : nullptr);
  nlohmann::json windows = nlohmann::json::array();
  for (const OdometryWindowRecord& window : result.windows) {
    windows.push_back({{"section", window.section},
                       {"first_keyframe", window.first_keyframe},
                       {"last_keyframe", window.last_keyframe},
                       {"points", window.points},
                       {"straight", window.straight},
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
  std::vector<Junction> junctions;
  report.Extra("t_intersections") = TIntersectionsJson(result, &junctions);
  for (const TIntersectionRecord& t : result.t_intersections) {
    if (t.rejection.empty() && t.phi_start_at_range_end) {
      report.Warn(fmt::format(
          "the T-intersection of key frames {}-{} took its angle (phi {:.1f} deg) from the last "
          "of its starts ({:+.0f} deg from the chained turn): the best angle may lie beyond the "
          "starts tried",
          t.red_keyframe, t.blue_keyframe, t.model[kPhi] * 180.0 / M_PI, t.start_phi_offset_deg));
    }
    if (t.rejection.empty()) continue;
    report.Warn("the T-intersection of key frames " + std::to_string(t.red_keyframe) + "-" +
                std::to_string(t.blue_keyframe) + " kept its chained poses (" + t.rejection +
                "): the two-cylinder model did not join its straight sections" +
                (t.modelled ? "; its centre in junctions.yaml is the end cylinders' estimate"
                            : ", and it is not in junctions.yaml"));
  }
  report.Extra("loop_closure") = LoopClosureJson(result.loop_closure);
  // A corner the closure turned by more than a degree (a T's angle, when the T pass got it
  // right, is off by 0.2-0.7 degrees through its end cylinders alone) was wrong by about that
  // much before it: the user should know which junction's angle the loop corrected.
  for (const TTurnChange& change : result.loop_closure.t_turn_changes) {
    if (change.turn_change_deg <= 1.0) continue;
    report.Warn(fmt::format(
        "loop closure turned the T-intersection of section {} by {:.2f} deg: its turn before the "
        "closure was off by about that much",
        change.section, change.turn_change_deg));
  }
  if (!result.loop_closure.applied &&
      result.loop_closure.why_not.rfind("the run's turns", 0) == 0) {
    report.Warn("no loop closure: " + result.loop_closure.why_not);
  }
  nlohmann::json failed = nlohmann::json::array();
  for (const FisheyeFrameFailure& failure : result.failed_frames) {
    failed.push_back(
        {{"index", failure.index}, {"name", failure.name}, {"reason", failure.reason}});
  }
  report.Extra("failed_frames") = failed;
  report.Extra("unreadable_frames") = result.unreadable_frames;
  // Without a point the run fails below, and its error says this.
  if (!result.failed_frames.empty() && !result.points.empty()) {
    report.Warn(std::to_string(result.failed_frames.size()) +
                " frames could not be matched to their key frame and were skipped (see "
                "failed_frames)");
  }
  report.Extra("trajectory_note") =
      "key frame poses are estimated; other frames are interpolated between key frames; the "
      "world frame is the first key frame's camera frame";

  if (result.points.empty()) {
    // No run.json is written, so the error carries what the user needs to see why.
    std::string unmatched;
    if (!result.failed_frames.empty()) {
      const FisheyeFrameFailure& first = result.failed_frames.front();
      unmatched = "; " + std::to_string(result.failed_frames.size()) + " of " +
                  std::to_string(result.frames) +
                  " frames could not be matched to their key frame (the first, " + first.name +
                  ": " + first.reason +
                  "): the frames show too little of the wall's texture to match (dark, blurred, "
                  "plain or noisy)";
    }
    throw RunFailedError("no point of the wall was triangulated in " +
                         std::to_string(result.keyframes.size()) +
                         " key frames, so the scale and the path are not measured" + unmatched);
  }
  // Key frames carry the measurements and the frames between them are interpolated: a key frame
  // whose relative pose was rejected continued the recent motion, and so did the frames since the
  // key frame before it.
  std::vector<FrameState> states(result.frames, FrameState::kMeasured);
  for (std::size_t k = 1; k < result.keyframes.size(); ++k) {
    if (!result.keyframes[k].direction_rejected) continue;
    for (int i = result.keyframes[k - 1].frame_index + 1;
         i <= result.keyframes[k].frame_index && i < result.frames; ++i) {
      states[i] = FrameState::kPredicted;
    }
  }
  for (const FisheyeFrameFailure& failure : result.failed_frames) {
    if (failure.index >= 0 && failure.index < result.frames) {
      states[failure.index] = FrameState::kNotLocalised;
    }
  }
  states.insert(states.end(), result.unreadable_frames.size(), FrameState::kNotLocalised);
  // A scale the windows did not confirm is not trusted (on faint, noisy texture most windows
  // are rejected and the single steps' bias stays).
  std::vector<int> keyframe_frames;
  for (const FisheyeKeyframe& keyframe : result.keyframes) {
    keyframe_frames.push_back(keyframe.frame_index);
  }
  std::vector<std::string> reasons = WindowConfirmationReasons(result, options);
  for (const std::string& reason : RevisitReasons(result.loop_closure)) reasons.push_back(reason);
  // A turn's angle rests on the T model alone unless a closed loop confirms it: the positions
  // past it are then unconfirmed, while the distances along each pipe stand.
  std::vector<std::string> junction_names;
  std::size_t next_junction = 0;
  for (const TIntersectionRecord& t : result.t_intersections) {
    junction_names.push_back(t.modelled ? junctions[next_junction++].name : "");
  }
  run.SetQuality(
      states, reasons, KeyframeQualityLimits(keyframe_frames),
      UnconfirmedTurnReasons(result.t_intersections, junction_names, result.loop_closure));
  run.WriteTrajectory(result.trajectory);
  run.WriteKeyFrames(result.keyframe_trajectory);
  if (!result.keyframe_trajectory_before_loop_closure.empty()) {
    run.WriteKeyFramesBeforeLoopClosure(result.keyframe_trajectory_before_loop_closure);
  }
  WriteSparsePly(result, &run);
  std::vector<PipeViewClass> initial, filtered;
  for (const FisheyeKeyframe& keyframe : result.keyframes) {
    initial.push_back(keyframe.initial_class);
    filtered.push_back(keyframe.filtered_class);
  }
  run.WriteImage("classification.png", DrawClassificationStrip(initial, filtered));
  WriteEstimatedJunctions(run.staging_path() / "junctions.yaml", junctions);
  if (dense_writer) dense_writer->Finish(result.dense_map, options.dense_map, &run);
  if (ground_truth) {
    run.WriteMetrics(*ground_truth, result.trajectory, manifest.groundtruth_path.string());
  }
  const double seconds = total.ElapsedSeconds();
  report.Extra("fps_end_to_end") = result.frames / std::max(1e-9, seconds);
  run.Commit();
  spdlog::info(
      "map: {} frames, {} key frames, {} sections, {} points in {:.1f} s ({:.2f} frames/s); wrote "
      "{}",
      result.frames, result.keyframes.size(), result.sections.size(), result.points.size(), seconds,
      result.frames / std::max(1e-9, seconds), flags.out);
  return kExitSuccess;
}

}  // namespace

SubcommandRunner SetupMapCommand(CLI::App* command) {
  auto flags = std::make_shared<RunFlags>();
  AddRunFlags(command, flags.get(), "YAML file of mapping options (see --list-keys)");
  return [flags] { return RunMap(*flags); };
}

}  // namespace pipescope
