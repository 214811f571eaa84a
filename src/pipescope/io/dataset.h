#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "pipescope/util/output_paths.h"

namespace pipescope {

// The inner radius of a pipe a camera can be carried through. A radius outside is a typo or a
// unit mistake (millimetres for metres), and is refused rather than mapped into nonsense.
inline constexpr double kMinPipeRadiusM = 1e-3;
inline constexpr double kMaxPipeRadiusM = 10.0;

// A dataset directory's manifest, `dataset.yaml` (GUIDE §4). Paths are absolute or relative to
// the working directory once read: relative paths in the file are resolved against the
// manifest's folder.
struct DatasetManifest {
  std::filesystem::path manifest_path;  // empty for a plain image folder
  std::string name;
  std::filesystem::path camera_path;
  std::filesystem::path images_dir;  // exactly one of images_dir and video_path is set
  std::filesystem::path video_path;
  double fps = 0.0;  // used when there is no timestamps file
  std::filesystem::path timestamps_path;
  std::optional<double> inner_radius_m;  // pipe.inner_radius_m
  // pipe.up: the pipe frame's "up" (12 o'clock, GUIDE §4), a unit vector in the frame of the
  // ground truth and of straight-pipe trajectories. Unset: the camera's upright at the first frame.
  std::optional<Eigen::Vector3d> pipe_up;
  std::optional<double> reference_scale_px_per_m;  // 000 §3.3, dense methods
  std::filesystem::path gain_mask_path;
  std::filesystem::path groundtruth_path;
  std::filesystem::path scene_path;
};

// Reads and checks `dataset.yaml`; every referenced file must exist. Throws InputError naming
// the manifest and the key at fault.
DatasetManifest ReadDatasetManifest(const std::filesystem::path& manifest_path);

// Writes `dataset.yaml` atomically, with paths relative to the manifest's folder where they lie
// below it.
void WriteDatasetManifest(const std::filesystem::path& manifest_path,
                          const DatasetManifest& manifest);

// Command-line overrides for opening a dataset.
struct DatasetOverrides {
  std::filesystem::path camera_path;     // --camera
  std::optional<double> inner_radius_m;  // --radius
  std::optional<double> fps;             // --fps
};

// Opens what a user names as DATASET: a dataset directory holding dataset.yaml, a manifest file,
// or a plain folder of images (which then needs --camera and --radius). Overrides replace the
// manifest's values.
DatasetManifest OpenDataset(const std::filesystem::path& dataset,
                            const DatasetOverrides& overrides = {});

// The manifest's path for error messages, or "dataset" when it has none (a plain image folder).
std::string ManifestName(const DatasetManifest& manifest);

// What a command reads of a dataset (`dataset` as the user named it), for
// RefuseOutputOverInputs(): the dataset, its images or video, calibration and ground truth.
std::vector<NamedInput> DatasetInputs(const std::filesystem::path& dataset,
                                      const DatasetManifest& manifest);

// The pipe radius, or InputError telling the user how to give it.
double RequireInnerRadius(const DatasetManifest& manifest);

}  // namespace pipescope
