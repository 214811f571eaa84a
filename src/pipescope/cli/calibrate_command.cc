// `pipescope calibrate`: camera calibration from checkerboard images (GUIDE §5; issue 4,
// 001 §II). Writes camera.yaml and, beside it, calibration.json with the per-image errors.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "pipescope/camera/calibration.h"
#include "pipescope/camera/camera_io.h"
#include "pipescope/cli/flag_checks.h"
#include "pipescope/cli/subcommand.h"
#include "pipescope/io/image_source.h"
#include "pipescope/util/atomic_file.h"
#include "pipescope/util/error.h"
#include "pipescope/util/median.h"
#include "pipescope/util/output_paths.h"
#include "pipescope/util/progress.h"

namespace pipescope {
namespace {

namespace fs = std::filesystem;

// A view whose RMS exceeds this multiple of the median is flagged in the table: a misdetected
// corner or a blurred image, worth a look.
constexpr double kSuspectViewFactor = 3.0;
// Fewer views leave the focal length unconstrained; a larger RMS means the corners were matched
// to the wrong board (or the images are not of one camera), whatever the fit reports.
constexpr std::size_t kMinViews = 3;
constexpr double kMaxRmsPx = 2.0;

struct CalibrateFlags {
  std::string model;
  std::string board;
  double square_m = 0.0;
  std::vector<std::string> images;
  std::string out;
  std::string report;
};

std::string SizeText(const cv::Size& size) {
  return std::to_string(size.width) + "x" + std::to_string(size.height);
}

struct Detections {
  cv::Size image_size;
  std::vector<CalibrationView> views;
  std::vector<std::string> without_board;
  std::vector<std::string> unreadable;
};

// Reads every image and finds the board in it. Images of another size than the first are an
// InputError (one calibration describes one image size); unreadable images and images without
// the board are listed and skipped.
Detections DetectBoards(const std::vector<fs::path>& paths, const CheckerboardSpec& board) {
  Detections detections;
  fs::path first;
  ProgressBar progress("detect", paths.size());
  for (std::size_t i = 0; i < paths.size(); ++i) {
    const std::string name = paths[i].string();
    const cv::Mat image = cv::imread(name, cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR);
    if (image.empty()) {
      detections.unreadable.push_back(name);
      spdlog::warn("cannot read image {}; skipped", name);
    } else {
      if (first.empty()) {
        first = paths[i];
        detections.image_size = image.size();
      } else if (image.size() != detections.image_size) {
        throw InputError("image " + name + " is " + SizeText(image.size()) + " but " +
                         first.string() + " is " + SizeText(detections.image_size) +
                         ": all calibration images must come from one camera at one size");
      }
      CalibrationView view;
      view.name = name;
      if (DetectCheckerboardCorners(image, board, &view.corners)) {
        detections.views.push_back(std::move(view));
      } else {
        detections.without_board.push_back(name);
      }
    }
    progress.Update(i + 1);
  }
  progress.Finish();
  return detections;
}

void PrintReport(const CalibrationResult& result, const std::vector<CalibrationView>& views) {
  const double median = UpperMedian(result.view_rms_px);
  std::size_t width = 5;
  for (const CalibrationView& view : views) width = std::max(width, view.name.size());
  std::printf("%-*s  %7s  %8s\n", static_cast<int>(width), "image", "corners", "rms_px");
  for (std::size_t v = 0; v < views.size(); ++v) {
    std::printf("%-*s  %7zu  %8.4f%s\n", static_cast<int>(width), views[v].name.c_str(),
                views[v].corners.size(), result.view_rms_px[v],
                result.view_rms_px[v] > kSuspectViewFactor * median ? "  <- check this image" : "");
  }
  const Camera& camera = result.camera;
  std::printf("\nmodel       %s, %dx%d\n", camera.ModelName().c_str(), camera.Width(),
              camera.Height());
  std::printf("params      %s\n           ", CameraModelParamsInfo(camera.ModelId()).c_str());
  for (double value : camera.Params()) std::printf(" %.10g", value);
  std::printf("\nrms         %.4f px over %d corners in %zu images\n", result.rms_px,
              result.num_corners, views.size());
  std::printf("max angle   %.1f deg from the optical axis\nmethod      %s\n", result.max_angle_deg,
              result.method.c_str());
}

nlohmann::json ReportJson(const CalibrationResult& result, const CheckerboardSpec& board,
                          const std::vector<CalibrationView>& views, const Detections& detections) {
  nlohmann::json report;
  report["model"] = result.camera.ModelName();
  report["width"] = result.camera.Width();
  report["height"] = result.camera.Height();
  report["params"] = result.camera.Params();
  report["params_info"] = CameraModelParamsInfo(result.camera.ModelId());
  report["board"] = {{"cols", board.cols}, {"rows", board.rows}, {"square_m", board.square_m}};
  report["rms_px"] = result.rms_px;
  report["corners"] = result.num_corners;
  report["max_angle_deg"] = result.max_angle_deg;
  report["method"] = result.method;
  nlohmann::json per_view = nlohmann::json::array();
  for (std::size_t v = 0; v < views.size(); ++v) {
    per_view.push_back({{"image", views[v].name}, {"rms_px", result.view_rms_px[v]}});
  }
  report["views"] = per_view;
  report["images_without_board"] = detections.without_board;
  report["unreadable_images"] = detections.unreadable;
  return report;
}

int RunCalibrate(const CalibrateFlags& flags) {
  const fs::path report_path = flags.report.empty()
                                   ? fs::path(flags.out).parent_path() / "calibration.json"
                                   : fs::path(flags.report);
  if (fs::is_directory(flags.out)) throw InputError("--out " + flags.out + " is a folder");
  if (fs::is_directory(report_path)) {
    throw InputError("--report " + report_path.string() + " is a folder; name a .json file");
  }
  if (fs::weakly_canonical(fs::absolute(report_path)) ==
      fs::weakly_canonical(fs::absolute(flags.out))) {
    throw InputError("--report and --out name the same file, " + flags.out +
                     ": the report would replace the calibration");
  }
  const CameraModelId model_id = CameraModelFromName(flags.model);
  CheckerboardSpec board = ParseCheckerboardSize(flags.board, "--board");
  board.square_m = flags.square_m;
  const std::vector<fs::path> paths = ExpandImageArguments(flags.images);
  for (const fs::path& image : paths) {
    RefuseOutputOverInputs(flags.out, "--out", {{image, "an input image"}});
    RefuseOutputOverInputs(report_path, "--report", {{image, "an input image"}});
  }
  spdlog::info("finding {}x{} inner corners in {} images", board.cols, board.rows, paths.size());
  const Detections detections = DetectBoards(paths, board);
  if (!detections.without_board.empty()) {
    std::string list;
    for (const std::string& name : detections.without_board) list += "\n  " + name;
    spdlog::warn("no {}x{} board found in {} of {} images; calibrating without them:{}", board.cols,
                 board.rows, detections.without_board.size(), paths.size(), list);
  }
  if (detections.views.empty()) {
    throw InputError("no " + flags.board + " checkerboard found in any of the " +
                     std::to_string(paths.size()) +
                     " images; --board counts inner corners (COLSxROWS), not squares");
  }
  if (detections.views.size() < kMinViews) {
    // One or two views leave the focal length free along the viewing direction: the fit
    // "succeeds" several times off.
    throw InputError("the " + flags.board + " board was found in only " +
                     std::to_string(detections.views.size()) + " of the images; at least " +
                     std::to_string(kMinViews) +
                     " views are needed (take 15-25, tilted, covering the whole image)");
  }
  if (detections.views.size() < 10) {
    spdlog::warn(
        "only {} views of the board: the calibration is poorly constrained; take 15-25 "
        "views, tilted, covering the whole image",
        detections.views.size());
  }
  const CalibrationResult result = CalibrateCamera(
      model_id, detections.image_size.width, detections.image_size.height, board, detections.views);
  PrintReport(result, detections.views);
  if (!(result.rms_px <= kMaxRmsPx)) {
    char rms[32];
    std::snprintf(rms, sizeof(rms), "%.3g", result.rms_px);
    throw InputError(std::string("the fit leaves ") + rms +
                     " px RMS between the board and its image: check --board (inner corners, "
                     "COLSxROWS) and the images; nothing was written");
  }
  CheckCameraIsPlausible("the fitted calibration", result.camera);

  WriteCameraYaml(flags.out, result.camera);
  WriteTextFileAtomically(report_path,
                          ReportJson(result, board, detections.views, detections).dump(2) + "\n");
  spdlog::info("wrote {} and {}", flags.out, report_path.string());
  return kExitSuccess;
}

}  // namespace

SubcommandRunner SetupCalibrateCommand(CLI::App* command) {
  auto flags = std::make_shared<CalibrateFlags>();
  command->add_option("--model", flags->model, "Camera model to fit")
      ->required()
      ->check(CLI::IsMember(CameraModelNames()));
  command->add_option("--board", flags->board, "Inner corners of the checkerboard, COLSxROWS")
      ->required();
  command->add_option("--square-m", flags->square_m, "Side of a square, metres")
      ->required()
      ->check(FinitePositive(10.0));
  command->add_option("images", flags->images, "Images or folders of images of the board")
      ->required();
  command->add_option("--out", flags->out, "camera.yaml to write")->required();
  command->add_option("--report", flags->report,
                      "RMS and per-image errors as JSON (default: calibration.json beside --out)");
  return [flags] { return RunCalibrate(*flags); };
}

}  // namespace pipescope
