#include "pipescope/report/run_directory.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "pipescope/eval/metrics_report.h"
#include "pipescope/eval/trajectory_metrics.h"
#include "pipescope/geometry/clock_position.h"
#include "pipescope/mapping/mosaic_io.h"
#include "pipescope/report/report_page.h"
#include "pipescope/util/atomic_file.h"
#include "pipescope/util/error.h"
#include "pipescope/util/median.h"

namespace pipescope {

namespace {

// A run of one command is not replaced by a run of another (`map` over an `odometry` run).
const std::filesystem::path& RequireSameCommand(const std::filesystem::path& out,
                                                const std::string& command) {
  const std::filesystem::path run_json = out / "run.json";
  if (!std::filesystem::is_regular_file(run_json)) return out;
  std::string earlier;
  try {
    earlier = nlohmann::json::parse(ReadTextFile(run_json)).value("command", "");
  } catch (const nlohmann::json::exception&) {
  }
  if (earlier != command) {
    throw InputError("--out " + out.string() + " holds " +
                     (earlier.empty() ? std::string("a run.json of unknown origin")
                                      : "a `" + earlier + "` run") +
                     "; refusing to replace it with a `" + command + "` run");
  }
  return out;
}

// Frames whose step goes against the steps on both sides of it, by more than half the median
// step: a path does not zig-zag for one frame, frames out of order (or a failed registration)
// do. The turnaround of an out-and-back run reverses once, not for one frame.
std::vector<double> OneFrameReversals(const Trajectory& trajectory) {
  std::vector<Eigen::Vector3d> steps;
  for (std::size_t i = 1; i < trajectory.size(); ++i) {
    steps.push_back(trajectory[i].position - trajectory[i - 1].position);
  }
  std::vector<double> lengths;
  for (const Eigen::Vector3d& step : steps) lengths.push_back(step.norm());
  const double median = lengths.empty() ? 0.0 : UpperMedian(lengths);
  std::vector<double> times;
  for (std::size_t i = 1; i + 1 < steps.size(); ++i) {
    if (steps[i].norm() > 0.5 * median && median > 0.0 && steps[i].dot(steps[i - 1]) < 0.0 &&
        steps[i].dot(steps[i + 1]) < 0.0) {
      times.push_back(trajectory[i + 1].timestamp);
    }
  }
  return times;
}

}  // namespace

RunDirectory::RunDirectory(const std::filesystem::path& out, std::string command,
                           std::string method)
    : staging_(RequireSameCommand(out, command), "--out", "run.json"),
      report_(command),
      command_(command) {
  report_.SetMethod(method);
}

void RunDirectory::SetDataset(const DatasetManifest& manifest) {
  dataset_ = manifest;
  const auto absolute = [](const std::filesystem::path& path) {
    return path.empty() ? nlohmann::json(nullptr)
                        : nlohmann::json(std::filesystem::absolute(path).string());
  };
  report_.Extra("inputs") = {
      {"dataset",
       absolute(manifest.manifest_path.empty() ? manifest.images_dir : manifest.manifest_path)},
      {"images", absolute(manifest.images_dir)},
      {"video", absolute(manifest.video_path)},
      {"camera", absolute(manifest.camera_path)},
      {"groundtruth", absolute(manifest.groundtruth_path)},
      {"scene", absolute(manifest.scene_path)},
      {"radius_m", manifest.inner_radius_m ? nlohmann::json(*manifest.inner_radius_m)
                                           : nlohmann::json(nullptr)}};
  std::filesystem::copy_file(manifest.camera_path, staging_.path() / "camera.yaml",
                             std::filesystem::copy_options::overwrite_existing);
}

void RunDirectory::WriteStations(const Trajectory& trajectory) {
  StationOptions options;
  options.line = survey_line_        ? *survey_line_
                 : command_ == "map" ? SurveyLine::kTravelledPath
                                     : SurveyLine::kStraightAxis;
  const Eigen::Matrix3d first_rotation = trajectory.front().rotation.toRotationMatrix();
  std::string up_source;
  if (dataset_->pipe_up && options.line == SurveyLine::kStraightAxis) {
    options.up = *dataset_->pipe_up;
    up_source = "pipe.up of the dataset";
  } else if (dataset_->pipe_up && !dataset_->groundtruth_path.empty()) {
    // A map's frame is its first camera's; the ground truth's pose of that frame carries pipe.up
    // (given in the pipe frame) into it.
    const Trajectory truth = ReadTumTrajectory(dataset_->groundtruth_path);
    const auto nearest = std::min_element(
        truth.begin(), truth.end(), [&](const StampedPose& a, const StampedPose& b) {
          return std::abs(a.timestamp - trajectory.front().timestamp) <
                 std::abs(b.timestamp - trajectory.front().timestamp);
        });
    options.up =
        first_rotation * nearest->rotation.toRotationMatrix().transpose() * *dataset_->pipe_up;
    up_source =
        "pipe.up of the dataset, carried into the map's frame by the ground truth's pose "
        "of the first frame";
  } else {
    options.up = CameraUpright(first_rotation);
    up_source = "the camera's upright at the first frame";
    if (dataset_->pipe_up) {
      up_source +=
          " (pipe.up is given in the pipe frame, which a map run does not know without "
          "ground truth)";
    }
  }
  const std::vector<Station> stations =
      ComputeStations(trajectory, FrameIndicesByTime(trajectory, *dataset_), options);
  WriteStationsCsv(staging_.path() / "stations.csv", stations);
  double low = 0.0, high = 0.0;
  long long undefined_roll = 0;
  for (const Station& station : stations) {
    low = std::min(low, station.distance_m);
    high = std::max(high, station.distance_m);
    undefined_roll += std::isfinite(station.roll_clock_deg) ? 0 : 1;
  }
  report_.Extra("inspection") = {
      {"survey_line", SurveyLineName(options.line)},
      {"survey_direction_first",
       {stations.front().travel.x(), stations.front().travel.y(), stations.front().travel.z()}},
      {"up", {options.up.x(), options.up.y(), options.up.z()}},
      {"up_source", up_source},
      {"distance_min_m", low},
      {"distance_max_m", high}};
  if (undefined_roll > 0) {
    report_.Warn(std::to_string(undefined_roll) +
                 " frames have no clock position of their roll: the pipe runs along \"up\" there");
  }
}

void RunDirectory::WriteTrajectory(const Trajectory& trajectory) {
  constexpr double kFarthestM = 1e6;
  if (trajectory.empty()) throw RunFailedError("no frame was localised");
  for (const StampedPose& pose : trajectory) {
    if (!pose.position.allFinite() || !pose.rotation.coeffs().allFinite()) {
      throw RunFailedError("the pose at time " + std::to_string(pose.timestamp) +
                           " is not finite: the estimator diverged");
    }
    if ((pose.position - trajectory.front().position).norm() > kFarthestM) {
      throw RunFailedError("the pose at time " + std::to_string(pose.timestamp) +
                           " lies more than 1000 km from the start: the estimator diverged");
    }
  }
  // Crawlers, robots and tethered cameras move at under a few metres a second; a step faster
  // than this is an estimate that ran away, not a measurement.
  constexpr double kFastestMPerS = 20.0;
  for (std::size_t i = 1; i < trajectory.size(); ++i) {
    const double step_m = (trajectory[i].position - trajectory[i - 1].position).norm();
    const double dt_s = trajectory[i].timestamp - trajectory[i - 1].timestamp;
    if (step_m > kFastestMPerS * std::max(dt_s, 1e-3)) {
      throw RunFailedError("the camera moves " + std::to_string(step_m) + " m in " +
                           std::to_string(dt_s) + " s at time " +
                           std::to_string(trajectory[i].timestamp) +
                           ": faster than 20 m/s, the estimator diverged");
    }
  }
  const std::vector<double> reversals = OneFrameReversals(trajectory);
  if (!reversals.empty()) {
    std::string times;
    for (std::size_t i = 0; i < std::min<std::size_t>(reversals.size(), 5); ++i) {
      times += (i == 0 ? "" : ", ") + std::to_string(reversals[i]);
    }
    report_.Warn(std::to_string(reversals.size()) +
                 " frame(s) move against both their neighbours (at t = " + times +
                 (reversals.size() > 5 ? ", ..." : "") +
                 " s): are the frames out of order, or did their registration fail?");
    report_.Extra("reversed_frames_t") = reversals;
  }
  WriteTumTrajectory(staging_.path() / "trajectory.tum", trajectory);
  if (dataset_) WriteStations(trajectory);
}

void RunDirectory::WriteKeyFrames(const Trajectory& key_frames) {
  WriteTumTrajectory(staging_.path() / "keyframes.tum", key_frames);
}

void RunDirectory::WriteKeyFramesBeforeLoopClosure(const Trajectory& key_frames) {
  WriteTumTrajectory(staging_.path() / "keyframes_before_loop_closure.tum", key_frames);
}

void RunDirectory::WriteSparsePoints(const std::vector<Eigen::Vector3d>& points,
                                     const std::vector<PlyColour>& colours,
                                     const std::string& comment) {
  WritePlyPoints(staging_.path() / "points_sparse.ply", points, colours, comment);
}

void RunDirectory::WriteMosaic(const cv::Mat& mosaic, const std::string& kind, double pixel_m,
                               cv::Point2d origin_m) {
  if (mosaic.empty()) return;
  WriteMosaicPng(staging_.path() / "mosaic.png", mosaic);
  report_.Extra("mosaic") = {
      {"kind", kind},
      {"width_px", mosaic.cols},
      {"height_px", mosaic.rows},
      {"pixel_m", pixel_m > 0.0 ? nlohmann::json(pixel_m) : nlohmann::json(nullptr)},
      {"origin_h_m", origin_m.x},
      {"origin_s_m", origin_m.y}};
}

void RunDirectory::WriteImage(const std::string& name, const cv::Mat& image) {
  std::vector<uchar> encoded;
  const std::string extension = std::filesystem::path(name).extension().string();
  if (!cv::imencode(extension, image, encoded)) {
    throw std::runtime_error("could not encode " + name);
  }
  WriteTextFileAtomically(staging_.path() / name, std::string(encoded.begin(), encoded.end()));
}

std::optional<Metrics> RunDirectory::WriteMetrics(const Trajectory& ground_truth,
                                                  const Trajectory& estimate,
                                                  const std::string& ground_truth_name) {
  Metrics metrics;
  try {
    metrics = EvaluateTrajectory(ground_truth, estimate, {});
  } catch (const InputError& error) {
    report_.Warn("no metrics.json: the trajectory cannot be compared with the ground truth " +
                 ground_truth_name + ": " + error.what());
    return std::nullopt;
  }
  nlohmann::json metrics_json = MetricsToJson(metrics);
  if (quality_) {
    // Predicted frames are in the trajectory and so in the metrics; say how many.
    metrics_json["frames_predicted"] = quality_->predicted;
    metrics_json["frames_not_localised"] = quality_->not_localised;
    metrics_json["quality_verdict"] = quality_->reliable ? "reliable" : "unreliable";
    metrics_json["quality_along_pipe_verdict"] =
        quality_->AlongPipeReliable() ? "reliable" : "unreliable";
  }
  WriteTextFileAtomically(staging_.path() / "metrics.json", metrics_json.dump(2) + "\n");
  std::cout << MetricsToTable(metrics);
  return metrics;
}

RunQuality RunDirectory::SetQuality(const std::vector<FrameState>& states,
                                    const std::vector<std::string>& model_reasons,
                                    const RunQualityLimits& limits,
                                    const std::vector<std::string>& position_reasons) {
  quality_ = AssessRunQuality(states, limits);
  for (const std::string& reason : model_reasons) {
    quality_->reliable = false;
    quality_->reasons.push_back(reason);
  }
  for (const std::string& reason : position_reasons) {
    quality_->reliable = false;
    quality_->reasons.push_back(reason);
    quality_->position_reasons.push_back(reason);
  }
  report_.Extra("quality") = RunQualityJson(*quality_, limits);
  if (quality_->reliable) {
    spdlog::info("{}", RunQualitySummary(*quality_));
  } else {
    report_.Warn(RunQualitySummary(*quality_));
  }
  return *quality_;
}

void RunDirectory::Commit() {
  report_.AddTiming("total", total_.ElapsedSeconds());
  report_.AddTiming("total_cpu", total_cpu_.ElapsedSeconds());
  report_.Write(staging_.path() / "run.json");
  // The report shows inspection coordinates, which need the dataset (SetDataset).
  if (write_report_ && dataset_) {
    const Timer report_time;
    const std::filesystem::path page = staging_.path() / "report.html";
    WriteReportPage(staging_.path(), page, {.shown_directory = staging_.target()});
    // run.json again, with the report's own time (docs/report.md: what the report costs a run).
    report_.AddTiming("report", report_time.ElapsedSeconds());
    report_.Write(staging_.path() / "run.json");
    spdlog::debug("report.html written in {:.2f} s", report_time.ElapsedSeconds());
  }
  staging_.Commit();
}

}  // namespace pipescope
