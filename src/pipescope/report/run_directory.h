#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "pipescope/eval/metrics.h"
#include "pipescope/io/dataset.h"
#include "pipescope/io/point_cloud_ply.h"
#include "pipescope/io/trajectory.h"
#include "pipescope/report/run_quality.h"
#include "pipescope/report/stations.h"
#include "pipescope/util/run_report.h"
#include "pipescope/util/staging_directory.h"
#include "pipescope/util/timer.h"

namespace pipescope {

// The one writer of a run directory (GUIDE §4), for every command that writes one (`odometry`,
// `map`): the files go into a staging folder beside the target, and Commit() writes run.json
// and puts the whole run in place, so the old run or the new one exists whole at every instant.
// A run that throws before Commit() leaves the target as it was.
class RunDirectory {
 public:
  // `out` is the target named by --out; it must be empty, missing, or an earlier run of the
  // same command (run.json), else InputError. `command` and `method` go into run.json.
  RunDirectory(const std::filesystem::path& out, std::string command, std::string method);

  // run.json's contents: options, counts, timings, warnings, extra sections.
  RunReport& report() { return report_; }
  const std::filesystem::path& staging_path() const { return staging_.path(); }

  // The dataset the run reads (with the command line's overrides): run.json's `inputs`, and a
  // copy of the calibration as camera.yaml, so `locate` and `report` need only the run. Call it
  // before WriteTrajectory, which then writes stations.csv too.
  void SetDataset(const DatasetManifest& manifest);

  // trajectory.tum: every frame that was localised. A trajectory no run can have (empty, not
  // finite, or beyond 1000 km from the start) is RunFailedError: the run must not be written.
  void WriteTrajectory(const Trajectory& trajectory);
  // keyframes.tum, for methods with key frames.
  void WriteKeyFrames(const Trajectory& key_frames);
  // keyframes_before_loop_closure.tum: the key frames before a loop closure moved them.
  void WriteKeyFramesBeforeLoopClosure(const Trajectory& key_frames);
  // points_sparse.ply (colours: empty or one per point).
  void WriteSparsePoints(const std::vector<Eigen::Vector3d>& points,
                         const std::vector<PlyColour>& colours = {},
                         const std::string& comment = "pipescope point cloud, metres, pipe frame");
  // mosaic.png and its description in run.json ("mosaic"), when `mosaic` is not empty;
  // pixel_m 0: the image-space map, which has no metric cell size.
  void WriteMosaic(const cv::Mat& mosaic, const std::string& kind, double pixel_m,
                   cv::Point2d origin_m);
  // Another image of the run (`name`, e.g. classification.png), written atomically.
  void WriteImage(const std::string& name, const cv::Mat& image);
  // metrics.json against `ground_truth` (every metric of docs/formats.md; `ground_truth_name`
  // is its file), printed as a table on standard output too. Returns the metrics, or nothing
  // with a warning when the two cannot be compared (too few poses in common): the run itself is
  // still written.
  std::optional<Metrics> WriteMetrics(const Trajectory& ground_truth, const Trajectory& estimate,
                                      const std::string& ground_truth_name);

  // The run's quality from each frame's state (report/run_quality.h): the `quality` block of
  // run.json, a warning when the run is unreliable, the summary line on the terminal, and the
  // counts in metrics.json (call it before WriteMetrics). Returns the assessment.
  // `model_reasons`: what the method found wrong with its own result beyond the frame states (a
  // fitted model that disagrees with the dataset); each makes the run unreliable.
  // `position_reasons`: what makes only the positions across the run's turns unconfirmed; each
  // makes the run unreliable, while its distances along the pipe stand.
  RunQuality SetQuality(const std::vector<FrameState>& states,
                        const std::vector<std::string>& model_reasons = {},
                        const RunQualityLimits& limits = {},
                        const std::vector<std::string>& position_reasons = {});

  // How stations.csv measures distance: by default along the straight axis for `odometry`, along
  // the travelled path for `map`; a method through bends (ekf) asks for the path.
  void SetSurveyLine(SurveyLine line) { survey_line_ = line; }

  // Whether Commit() writes report.html (the default; --no-report turns it off).
  void SetWriteReport(bool write) { write_report_ = write; }

  // Records the total wall and CPU seconds since construction, writes run.json (and report.html)
  // and moves the run into place.
  void Commit();

 private:
  Timer total_;
  ProcessCpuTimer total_cpu_;
  StagingDirectory staging_;
  RunReport report_;
  std::optional<RunQuality> quality_;
  std::string command_;
  std::optional<DatasetManifest> dataset_;
  bool write_report_ = true;
  std::optional<SurveyLine> survey_line_;

  // stations.csv and run.json's `inspection` block (GUIDE §4 inspection coordinates).
  void WriteStations(const Trajectory& trajectory);
};

}  // namespace pipescope
