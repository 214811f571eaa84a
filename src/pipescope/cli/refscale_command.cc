// `pipescope refscale`: the reference scale zeta of 000 §3.3 from one image of a circle-grid
// target on the pipe wall (GUIDE §5).
#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <regex>
#include <string>

#include "pipescope/camera/camera_io.h"
#include "pipescope/cli/flag_checks.h"
#include "pipescope/cli/subcommand.h"
#include "pipescope/image/reference_scale.h"
#include "pipescope/image/undistortion.h"
#include "pipescope/io/manifest_edit.h"
#include "pipescope/util/error.h"

namespace pipescope {
namespace {

struct RefscaleFlags {
  std::string image;
  std::string camera;
  std::string grid;
  double spacing_m = 0.0;
  std::string write;
};

// "COLSxROWS" -> circles per row and rows, each at least 2.
void ParseGrid(const std::string& text, int* cols, int* rows) {
  std::smatch match;
  if (!std::regex_match(text, match, std::regex(R"((\d{1,4})[xX](\d{1,4}))"))) {
    throw InputError("--grid " + text + ": expected COLSxROWS, e.g. 5x4");
  }
  *cols = std::stoi(match[1]);
  *rows = std::stoi(match[2]);
  if (*cols < 2 || *rows < 2) {
    throw InputError("--grid " + text + ": need at least 2 circles each way");
  }
}

cv::Mat ReadTargetImage(const std::filesystem::path& path) {
  if (!std::filesystem::is_regular_file(path)) {
    throw InputError("IMAGE " + path.string() + " does not exist");
  }
  cv::Mat image = cv::imread(path.string(), cv::IMREAD_UNCHANGED);
  if (image.empty()) throw InputError("IMAGE " + path.string() + " is not a readable image");
  return image;
}

int RunRefscale(const RefscaleFlags& flags) {
  int cols = 0, rows = 0;
  ParseGrid(flags.grid, &cols, &rows);
  if (!(flags.spacing_m > 0.0)) throw InputError("--spacing-m must be positive");
  std::filesystem::path manifest = flags.write;
  if (!manifest.empty()) {
    if (std::filesystem::is_directory(manifest)) manifest /= "dataset.yaml";
    if (!std::filesystem::is_regular_file(manifest)) {
      throw InputError("--write " + manifest.string() + " does not exist (name a dataset.yaml)");
    }
  }
  const Camera camera = ReadCamera(flags.camera);
  const cv::Mat image = ReadTargetImage(flags.image);
  if (image.cols != camera.Width() || image.rows != camera.Height()) {
    throw InputError("IMAGE " + flags.image + " is " + std::to_string(image.cols) + "x" +
                     std::to_string(image.rows) + " but --camera " + flags.camera +
                     " is calibrated for " + std::to_string(camera.Width()) + "x" +
                     std::to_string(camera.Height()));
  }

  const std::optional<std::vector<Eigen::Vector2d>> centres = DetectCircleGrid(image, cols, rows);
  if (!centres) {
    throw InputError("IMAGE " + flags.image + ": no " + flags.grid +
                     " grid of dark circles on a light card found (check --grid: circles per "
                     "row x rows)");
  }
  // Centroids taken in the perspective image the dense methods register (000 §3.3, §4).
  const std::optional<std::vector<Eigen::Vector2d>> undistorted =
      UndistortedCircleCentroids(image, camera, *centres, cols, rows);
  if (!undistorted) {
    throw InputError("IMAGE " + flags.image +
                     ": a circle lies outside the perspective view of --camera " + flags.camera);
  }
  const cv::Point2d principal = PrincipalPoint(camera);
  ReferenceScale scale;
  try {
    scale = EstimateReferenceScale(*undistorted, cols, rows, flags.spacing_m,
                                   Eigen::Vector2d(principal.x, principal.y));
  } catch (const InputError& error) {
    throw InputError("IMAGE " + flags.image + ": " + error.what());
  }
  if (!scale.principal_point_on_target) {
    spdlog::warn("the target does not cover the image centre; zeta is extrapolated to it");
  }
  if (std::abs(scale.across_px_per_m / scale.px_per_m - 1.0) > 0.01) {
    spdlog::warn(
        "the scale across the image differs from the axial scale by {:.1f} %: is the camera "
        "looking squarely at the wall?",
        100.0 * (scale.across_px_per_m / scale.px_per_m - 1.0));
  }

  // Key: value lines, so scripts can read them.
  if (!(std::isfinite(scale.px_per_m) && scale.px_per_m > 0.0)) {
    throw InputError("IMAGE " + flags.image + ": the reference scale came out as " +
                     std::to_string(scale.px_per_m) + " px/m; check --spacing-m and --camera");
  }
  std::printf("reference_scale_px_per_m: %.6f\n", scale.px_per_m);
  std::printf("std_error_px_per_m: %.6f  # %.4f %%\n", scale.std_error_px_per_m,
              100.0 * scale.std_error_px_per_m / scale.px_per_m);
  std::printf("across_px_per_m: %.6f  # image y, around the pipe\n", scale.across_px_per_m);
  std::printf(
      "mean_spacing_px_per_m: %.6f  # 000 §3.3 plain mean of %d axial neighbour pairs, "
      "spread (std) %.6f\n",
      scale.mean_spacing_px_per_m, scale.neighbour_pairs, scale.spacing_std_px_per_m);
  std::printf("fit_rms_px: %.4f\n", scale.fit_rms_px);
  std::printf("principal_point_on_grid: [%.3f, %.3f]  # in spacings from the first circle\n",
              scale.principal_point_on_grid.x(), scale.principal_point_on_grid.y());
  if (!manifest.empty()) {
    SetTopLevelYamlNumber(manifest, "reference_scale_px_per_m", scale.px_per_m);
    spdlog::info("wrote reference_scale_px_per_m into {}", manifest.string());
  }
  return kExitSuccess;
}

}  // namespace

SubcommandRunner SetupRefscaleCommand(CLI::App* command) {
  auto flags = std::make_shared<RefscaleFlags>();
  command->add_option("IMAGE", flags->image, "Image of the circle-grid target on the wall")
      ->required();
  command->add_option("--camera", flags->camera, "Calibration of the camera (camera.yaml)")
      ->required();
  command->add_option("--grid", flags->grid, "Circles per row x rows, e.g. 5x4")->required();
  command->add_option("--spacing-m", flags->spacing_m, "Centre-to-centre spacing, metres")
      ->required()
      ->check(FinitePositive(10.0));
  command->add_option("--write", flags->write,
                      "Set reference_scale_px_per_m in this dataset.yaml (other keys kept)");
  return [flags] { return RunRefscale(*flags); };
}

}  // namespace pipescope
