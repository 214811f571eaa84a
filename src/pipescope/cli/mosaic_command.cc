// `pipescope mosaic`: stitches a dataset's gain-corrected frames at the poses of a trajectory
// into an appearance map (000 §6.1): unrolled on the pipe surface in (h, r phi) (Fig. 15, 17),
// or in image space at the image offsets the poses imply (Fig. 14, 16).
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <memory>
#include <optional>
#include <string>

#include "pipescope/camera/camera_io.h"
#include "pipescope/cli/flag_checks.h"
#include "pipescope/cli/subcommand.h"
#include "pipescope/image/gain_mask.h"
#include "pipescope/image/undistortion.h"
#include "pipescope/io/dataset.h"
#include "pipescope/io/image_source.h"
#include "pipescope/io/trajectory.h"
#include "pipescope/mapping/image_mosaic.h"
#include "pipescope/mapping/mosaic_io.h"
#include "pipescope/mapping/unrolled_mosaic.h"
#include "pipescope/util/error.h"
#include "pipescope/util/output_paths.h"
#include "pipescope/util/progress.h"

namespace pipescope {
namespace {

// Cells around the circumference when neither --pixel-mm nor the reference scale is given.
constexpr int kDefaultCellsAround = 1024;

struct MosaicFlags {
  std::string dataset;
  std::string trajectory;
  std::string out;
  std::string mode = "unrolled";
  std::optional<double> pixel_mm;
  double min_spacing_px = 50.0;  // 000 §6.1
  double max_dt_s = 0.01;
  std::string camera;
  std::optional<double> radius;
};

// The pose nearest in time to `timestamp`, if one lies within max_dt_s.
const StampedPose* PoseAt(const Trajectory& trajectory, double timestamp, double max_dt_s) {
  const auto after =
      std::lower_bound(trajectory.begin(), trajectory.end(), timestamp,
                       [](const StampedPose& pose, double time) { return pose.timestamp < time; });
  const StampedPose* best = nullptr;
  double best_dt = max_dt_s;
  if (after != trajectory.end() && after->timestamp - timestamp <= best_dt) {
    best = &*after;
    best_dt = after->timestamp - timestamp;
  }
  if (after != trajectory.begin() && timestamp - std::prev(after)->timestamp <= best_dt) {
    best = &*std::prev(after);
  }
  return best;
}

bool HasPngExtension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return extension == ".png";
}

// An unrolled mosaic must have a few cells around the pipe and fit in memory (a 0.0001 mm cell
// would ask for terabytes): refused before any frame is read.
void RequireMosaicSize(double cells_around, double cells_along, double pixel_m,
                       const std::string& source) {
  constexpr double kMinCellsAround = 16.0;
  constexpr double kMaxCells = 4e8;  // 400 megapixels: 1.6 GB of accumulators
  char message[200];
  if (cells_around < kMinCellsAround) {
    std::snprintf(message, sizeof(message),
                  "%s: %.6g mm cells leave only %.3g cells around the pipe (at least %g needed)",
                  source.c_str(), 1000.0 * pixel_m, cells_around, kMinCellsAround);
    throw InputError(message);
  }
  if (cells_around * cells_along > kMaxCells) {
    std::snprintf(message, sizeof(message),
                  "%s: %.6g mm cells make a %.3g x %.3g cell mosaic, beyond the %g cells this "
                  "command holds in memory; choose larger cells",
                  source.c_str(), 1000.0 * pixel_m, cells_along, cells_around, kMaxCells);
    throw InputError(message);
  }
}

int RunMosaic(const MosaicFlags& flags) {
  if (!HasPngExtension(flags.out)) {
    throw InputError("--out " + flags.out + ": the mosaic is written as PNG; name a .png file");
  }
  const bool unrolled = flags.mode == "unrolled";
  if (!unrolled && flags.pixel_mm) {
    throw InputError("--pixel-mm applies to --mode unrolled only (image mode keeps image pixels)");
  }
  const DatasetManifest manifest = OpenDataset(
      flags.dataset, {.camera_path = flags.camera, .inner_radius_m = flags.radius, .fps = {}});
  std::vector<NamedInput> inputs = DatasetInputs(flags.dataset, manifest);
  inputs.push_back({flags.trajectory, "--trajectory"});
  RefuseOutputOverInputs(flags.out, "--out", inputs);
  const Camera camera = ReadCamera(manifest.camera_path);
  Trajectory trajectory;
  try {
    trajectory = ReadTumTrajectory(flags.trajectory);
  } catch (const InputError& error) {
    throw InputError(std::string("--trajectory: ") + error.what());
  }
  cv::Mat gain_mask;
  if (!manifest.gain_mask_path.empty()) {
    gain_mask = ReadGainMask(manifest.gain_mask_path);
    if (gain_mask.cols != camera.Width() || gain_mask.rows != camera.Height()) {
      throw InputError("gain mask " + manifest.gain_mask_path.string() + " is " +
                       std::to_string(gain_mask.cols) + "x" + std::to_string(gain_mask.rows) +
                       " but the camera is " + std::to_string(camera.Width()) + "x" +
                       std::to_string(camera.Height()));
    }
  }

  std::optional<UnrolledMosaic> unrolled_mosaic;
  std::optional<ImageMosaic> image_mosaic;
  std::optional<Undistorter> undistorter;
  cv::Mat rectified_valid;
  double zeta = 0.0;
  if (unrolled) {
    const double radius = RequireInnerRadius(manifest);
    double pixel_m = 2.0 * M_PI * radius / kDefaultCellsAround;
    if (flags.pixel_mm) {
      pixel_m = *flags.pixel_mm / 1000.0;
    } else if (manifest.reference_scale_px_per_m) {
      // One cell per image pixel at the reference distance (000 §3.3).
      pixel_m = 1.0 / *manifest.reference_scale_px_per_m;
    }
    // Straight pipe along the world Z axis (GUIDE §3): the poses' h range, plus what a camera
    // sees around it; the PNG is cropped to the covered cells anyway.
    double h_min = trajectory.front().position.z(), h_max = h_min;
    for (const StampedPose& pose : trajectory) {
      h_min = std::min(h_min, pose.position.z());
      h_max = std::max(h_max, pose.position.z());
    }
    const double margin = 3.0 * radius;  // UnrolledMosaicOptions::max_axial_range_m's default
    RequireMosaicSize(2.0 * M_PI * radius / pixel_m, (h_max - h_min + 2.0 * margin) / pixel_m,
                      pixel_m, flags.pixel_mm ? "--pixel-mm" : "the default cell size");
    unrolled_mosaic.emplace(camera, radius, pixel_m, h_min - margin, h_max + margin);
    spdlog::info("unrolled mosaic: r = {:.4f} m, {:.3f} mm cells, {} cells around", radius,
                 1000.0 * pixel_m, unrolled_mosaic->grid().size.height);
  } else {
    if (!manifest.reference_scale_px_per_m) {
      throw InputError("--mode image needs the reference scale: add reference_scale_px_per_m to " +
                       (manifest.manifest_path.empty() ? std::string("the dataset manifest")
                                                       : manifest.manifest_path.string()) +
                       " (000 §3.3; pipescope refscale --write measures it)");
    }
    zeta = *manifest.reference_scale_px_per_m;
    image_mosaic.emplace(flags.min_spacing_px);
    undistorter.emplace(camera);
    // Rectified pixels whose ray the lens does not see would pull the mean towards 0.
    rectified_valid = undistorter->Apply(cv::Mat(camera.Height(), camera.Width(), CV_32F,
                                                 cv::Scalar(1.0f))) > 0.999f;
  }

  auto source = ImageSource::Open(
      manifest, {.expected_width = camera.Width(), .expected_height = camera.Height()});
  ProgressBar progress("mosaic", source->FrameCount());
  std::size_t frames = 0, without_pose = 0;
  std::optional<Eigen::Isometry3d> world_from_first_cam;
  while (std::optional<Frame> frame = source->Next()) {
    progress.Update(++frames);
    const StampedPose* pose = PoseAt(trajectory, frame->timestamp, flags.max_dt_s);
    if (pose == nullptr) {
      ++without_pose;
      continue;
    }
    const cv::Mat corrected =
        gain_mask.empty() ? frame->grey : ApplyGainMask(frame->grey, gain_mask);
    const Eigen::Isometry3d world_from_cam = ToIsometry(*pose);
    if (unrolled) {
      unrolled_mosaic->Add(corrected, world_from_cam);
    } else {
      if (!world_from_first_cam) world_from_first_cam = world_from_cam;
      image_mosaic->Add(undistorter->Apply(corrected),
                        ImageOffsetFromPoses(*world_from_first_cam, world_from_cam, zeta),
                        rectified_valid);
    }
  }
  progress.Finish();
  if (frames == 0) throw InputError(flags.dataset + ": no readable frames");
  if (frames == without_pose) {
    throw InputError("--trajectory " + flags.trajectory + ": no pose within " +
                     std::to_string(flags.max_dt_s) + " s of any frame's timestamp (" +
                     std::to_string(frames) + " frames)");
  }
  if (without_pose > 0) {
    spdlog::warn("{} of {} frames have no pose within {} s in {}: skipped", without_pose, frames,
                 flags.max_dt_s, flags.trajectory);
  }

  cv::Mat mosaic;
  if (unrolled) {
    const cv::Rect covered = unrolled_mosaic->CoveredRegion();
    if (covered.empty()) {
      throw InputError("--trajectory " + flags.trajectory +
                       ": no frame sees the pipe wall from its pose (is the pipe axis the Z "
                       "axis and the radius right?)");
    }
    mosaic = unrolled_mosaic->Render(covered);
    const UnrolledGrid& grid = unrolled_mosaic->grid();
    WriteMosaicPng(flags.out, mosaic);
    spdlog::info(
        "wrote {} ({}x{}): columns h = {:.4f}..{:.4f} m, rows s = r phi = {:.4f}..{:.4f} m, "
        "{} frames",
        flags.out, mosaic.cols, mosaic.rows, grid.h0_m + covered.x * grid.pixel_m,
        grid.h0_m + covered.br().x * grid.pixel_m, covered.y * grid.pixel_m,
        covered.br().y * grid.pixel_m, frames - without_pose);
  } else {
    mosaic = image_mosaic->Render();
    WriteMosaicPng(flags.out, mosaic);
    spdlog::info("wrote {} ({}x{}): {} of {} posed frames at least {} px apart", flags.out,
                 mosaic.cols, mosaic.rows, image_mosaic->frames_used(), frames - without_pose,
                 flags.min_spacing_px);
  }
  return kExitSuccess;
}

}  // namespace

SubcommandRunner SetupMosaicCommand(CLI::App* command) {
  auto flags = std::make_shared<MosaicFlags>();
  command->add_option("dataset", flags->dataset, "Dataset folder, manifest, or image folder")
      ->required();
  command->add_option("--trajectory", flags->trajectory, "Camera-to-world poses (TUM)")->required();
  command->add_option("--out", flags->out, "Mosaic to write (8-bit PNG)")->required();
  command
      ->add_option("--mode", flags->mode,
                   "unrolled: on the pipe surface in (h, r phi); image: in image space")
      ->check(CLI::IsMember({"unrolled", "image"}))
      ->capture_default_str();
  command
      ->add_option("--pixel-mm", flags->pixel_mm,
                   "Unrolled cell size, mm (default 1 / reference_scale_px_per_m, else "
                   "2 pi r / 1024)")
      ->check(FiniteRange(1e-3, 1e3));
  command
      ->add_option("--min-spacing-px", flags->min_spacing_px,
                   "Image mode: frames used lie at least this far apart (000 §6.1)")
      ->check(FiniteNonNegative(1e5))
      ->capture_default_str();
  command
      ->add_option("--max-dt", flags->max_dt_s,
                   "Largest time difference between a frame and its pose, seconds")
      ->check(FiniteNonNegative(3600.0))
      ->capture_default_str();
  command->add_option("--camera", flags->camera, "Calibration, for a plain image folder");
  command->add_option("--radius", flags->radius, "Pipe inner radius in metres")
      ->check(FiniteRange(kMinPipeRadiusM, kMaxPipeRadiusM));
  return [flags] { return RunMosaic(*flags); };
}

}  // namespace pipescope
