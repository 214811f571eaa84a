#include "pipescope/report/run_directory.h"

#include <iostream>
#include <opencv2/imgcodecs.hpp>

#include "pipescope/eval/metrics_report.h"
#include "pipescope/eval/trajectory_metrics.h"
#include "pipescope/mapping/mosaic_io.h"
#include "pipescope/util/atomic_file.h"
#include "pipescope/util/error.h"

namespace pipescope {

RunDirectory::RunDirectory(const std::filesystem::path& out, std::string command,
                           std::string method)
    : staging_(out, "--out", "run.json"), report_(std::move(command)) {
  report_.SetMethod(method);
}

void RunDirectory::WriteTrajectory(const Trajectory& trajectory) {
  WriteTumTrajectory(staging_.path() / "trajectory.tum", trajectory);
}

void RunDirectory::WriteKeyFrames(const Trajectory& key_frames) {
  WriteTumTrajectory(staging_.path() / "keyframes.tum", key_frames);
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

Metrics RunDirectory::WriteMetrics(const Trajectory& ground_truth, const Trajectory& estimate) {
  const Metrics metrics = EvaluateTrajectory(ground_truth, estimate, {});
  WriteTextFileAtomically(staging_.path() / "metrics.json", MetricsToJson(metrics).dump(2) + "\n");
  std::cout << MetricsToTable(metrics);
  return metrics;
}

void RunDirectory::Commit() {
  report_.AddTiming("total", total_.ElapsedSeconds());
  report_.AddTiming("total_cpu", total_cpu_.ElapsedSeconds());
  report_.Write(staging_.path() / "run.json");
  staging_.Commit();
}

}  // namespace pipescope
