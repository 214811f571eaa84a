#include "pipescope/io/dataset.h"

#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdio>
#include <sstream>
#include <system_error>
#include <vector>

#include "pipescope/io/yaml_helpers.h"
#include "pipescope/util/atomic_file.h"
#include "pipescope/util/error.h"

namespace pipescope {
namespace {

constexpr double kDefaultFolderFps = 30.0;

std::filesystem::path ResolvePath(const YAML::Node& root, const std::string& key,
                                  const std::filesystem::path& manifest_path, bool required,
                                  bool must_be_directory = false) {
  const auto value = OptionalYamlValue<std::string>(root, key, manifest_path);
  if (!value) {
    if (required) {
      throw InputError(manifest_path.string() + ": required key '" + key + "' is missing");
    }
    return {};
  }
  std::filesystem::path path(*value);
  if (path.is_relative()) path = manifest_path.parent_path() / path;
  // The error_code form: a name too long or a folder that cannot be searched must be the
  // manifest's error, not a std::filesystem exception that names neither the manifest nor the key.
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path, error);
  if (error && status.type() != std::filesystem::file_type::not_found) {
    throw InputError(manifest_path.string() + ": key '" + key + "' names " + path.string() +
                     ", which cannot be looked up: " + error.message());
  }
  const bool exists =
      must_be_directory ? std::filesystem::is_directory(status) : std::filesystem::exists(status);
  if (!exists) {
    throw InputError(manifest_path.string() + ": key '" + key + "' names " + path.string() +
                     (must_be_directory ? ", which is not a directory" : ", which does not exist"));
  }
  return path;
}

std::optional<double> PositiveValue(const YAML::Node& root, const std::string& key,
                                    const std::filesystem::path& manifest_path) {
  const auto value = OptionalYamlValue<double>(root, key, manifest_path);
  if (value && !(std::isfinite(*value) && *value > 0.0)) {
    throw InputError(manifest_path.string() + ": key '" + key + "' must be a positive number");
  }
  return value;
}

// pipe.up: three finite numbers, not all zero; returned with unit length.
std::optional<Eigen::Vector3d> UpVector(const YAML::Node& root,
                                        const std::filesystem::path& manifest_path) {
  const auto values = OptionalYamlValue<std::vector<double>>(root, "pipe.up", manifest_path);
  if (!values) return std::nullopt;
  const Eigen::Vector3d up = values->size() == 3
                                 ? Eigen::Vector3d((*values)[0], (*values)[1], (*values)[2])
                                 : Eigen::Vector3d::Zero();
  if (!up.allFinite() || up.norm() < 1e-9) {
    throw InputError(manifest_path.string() +
                     ": key 'pipe.up' must be three finite numbers, not all zero, e.g. [0, -1, 0]");
  }
  return up.normalized();
}

std::string RelativeToManifest(const std::filesystem::path& path,
                               const std::filesystem::path& manifest_dir) {
  if (path.empty()) return {};
  const std::filesystem::path absolute = std::filesystem::absolute(path).lexically_normal();
  const std::filesystem::path relative =
      absolute.lexically_relative(std::filesystem::absolute(manifest_dir).lexically_normal());
  if (!relative.empty() && *relative.begin() != "..") return relative.string();
  return absolute.string();
}

void CheckPositive(double value, const std::string& flag) {
  if (!(std::isfinite(value) && value > 0.0)) {
    throw InputError("flag " + flag + " must be a positive number");
  }
}

void CheckPipeRadius(double radius_m, const std::string& where) {
  if (!(radius_m >= kMinPipeRadiusM && radius_m <= kMaxPipeRadiusM)) {
    char buffer[160];
    std::snprintf(buffer, sizeof(buffer),
                  " is %.6g m; a pipe's inner radius lies between %g and %g m (metres, not mm?)",
                  radius_m, kMinPipeRadiusM, kMaxPipeRadiusM);
    throw InputError(where + buffer);
  }
}

}  // namespace

DatasetManifest ReadDatasetManifest(const std::filesystem::path& manifest_path) {
  const YAML::Node root = LoadYamlFile(manifest_path);
  if (!root.IsMap()) throw InputError(manifest_path.string() + ": expected a YAML mapping");
  DatasetManifest manifest;
  manifest.manifest_path = manifest_path;
  manifest.name = OptionalYamlValue<std::string>(root, "name", manifest_path)
                      .value_or(manifest_path.parent_path().filename().string());
  manifest.camera_path = ResolvePath(root, "camera", manifest_path, /*required=*/true);
  manifest.images_dir = ResolvePath(root, "images", manifest_path, false, true);
  manifest.video_path = ResolvePath(root, "video", manifest_path, false);
  if (manifest.images_dir.empty() == manifest.video_path.empty()) {
    throw InputError(manifest_path.string() +
                     ": give exactly one of the keys 'images' (a folder) and 'video' (a file)");
  }
  manifest.timestamps_path = ResolvePath(root, "timestamps", manifest_path, false);
  manifest.fps = PositiveValue(root, "fps", manifest_path).value_or(0.0);
  if (manifest.fps == 0.0 && manifest.timestamps_path.empty() && !manifest.images_dir.empty()) {
    throw InputError(manifest_path.string() + ": key 'fps' is missing (or give 'timestamps')");
  }
  manifest.inner_radius_m = PositiveValue(root, "pipe.inner_radius_m", manifest_path);
  if (manifest.inner_radius_m)
    CheckPipeRadius(*manifest.inner_radius_m,
                    manifest_path.string() + ": key 'pipe.inner_radius_m'");
  manifest.pipe_up = UpVector(root, manifest_path);
  manifest.reference_scale_px_per_m =
      PositiveValue(root, "reference_scale_px_per_m", manifest_path);
  manifest.gain_mask_path = ResolvePath(root, "gain_mask", manifest_path, false);
  manifest.groundtruth_path = ResolvePath(root, "groundtruth", manifest_path, false);
  manifest.scene_path = ResolvePath(root, "scene", manifest_path, false);
  return manifest;
}

void WriteDatasetManifest(const std::filesystem::path& manifest_path,
                          const DatasetManifest& manifest) {
  const std::filesystem::path dir =
      manifest_path.has_parent_path() ? manifest_path.parent_path() : ".";
  YAML::Emitter out;
  out.SetDoublePrecision(12);
  out << YAML::BeginMap;
  out << YAML::Key << "name" << YAML::Value << manifest.name;
  out << YAML::Key << "camera" << YAML::Value << RelativeToManifest(manifest.camera_path, dir);
  if (!manifest.images_dir.empty()) {
    out << YAML::Key << "images" << YAML::Value << RelativeToManifest(manifest.images_dir, dir);
  } else {
    out << YAML::Key << "video" << YAML::Value << RelativeToManifest(manifest.video_path, dir);
  }
  if (manifest.fps > 0) out << YAML::Key << "fps" << YAML::Value << manifest.fps;
  const std::pair<const char*, const std::filesystem::path*> optional_paths[] = {
      {"timestamps", &manifest.timestamps_path},
      {"gain_mask", &manifest.gain_mask_path},
      {"groundtruth", &manifest.groundtruth_path},
      {"scene", &manifest.scene_path}};
  for (const auto& [key, path] : optional_paths) {
    if (!path->empty()) out << YAML::Key << key << YAML::Value << RelativeToManifest(*path, dir);
  }
  if (manifest.inner_radius_m || manifest.pipe_up) {
    out << YAML::Key << "pipe" << YAML::Value << YAML::BeginMap;
    if (manifest.inner_radius_m)
      out << YAML::Key << "inner_radius_m" << YAML::Value << *manifest.inner_radius_m;
    if (manifest.pipe_up) {
      out << YAML::Key << "up" << YAML::Value << YAML::Flow << YAML::BeginSeq;
      for (int i = 0; i < 3; ++i) out << (*manifest.pipe_up)[i];
      out << YAML::EndSeq;
    }
    out << YAML::EndMap;
  }
  if (manifest.reference_scale_px_per_m) {
    out << YAML::Key << "reference_scale_px_per_m" << YAML::Value
        << *manifest.reference_scale_px_per_m;
  }
  out << YAML::EndMap;
  WriteTextFileAtomically(manifest_path, std::string(out.c_str()) + "\n");
}

DatasetManifest OpenDataset(const std::filesystem::path& dataset,
                            const DatasetOverrides& overrides) {
  DatasetManifest manifest;
  if (std::filesystem::is_regular_file(dataset)) {
    manifest = ReadDatasetManifest(dataset);
  } else if (std::filesystem::is_regular_file(dataset / "dataset.yaml")) {
    manifest = ReadDatasetManifest(dataset / "dataset.yaml");
  } else if (std::filesystem::is_directory(dataset)) {
    // A plain folder of images: the calibration and radius come from the flags.
    if (overrides.camera_path.empty()) {
      throw InputError(dataset.string() +
                       " has no dataset.yaml: give the calibration with --camera FILE");
    }
    manifest.name = dataset.filename().string();
    manifest.images_dir = dataset;
    manifest.fps = kDefaultFolderFps;
    if (!overrides.fps) {
      spdlog::warn(
          "{} has no dataset.yaml: assuming {} frames per second (give --fps, or write a "
          "dataset.yaml with key 'fps')",
          dataset.string(), kDefaultFolderFps);
    }
  } else {
    throw InputError("dataset not found: " + dataset.string() +
                     " (expected a folder with dataset.yaml, a manifest file, or an image folder)");
  }
  if (!overrides.camera_path.empty()) {
    if (!std::filesystem::is_regular_file(overrides.camera_path)) {
      throw InputError("flag --camera: file not found: " + overrides.camera_path.string());
    }
    manifest.camera_path = overrides.camera_path;
  }
  if (overrides.inner_radius_m) {
    CheckPipeRadius(*overrides.inner_radius_m, "flag --radius");
    manifest.inner_radius_m = overrides.inner_radius_m;
  }
  if (overrides.fps) {
    CheckPositive(*overrides.fps, "--fps");
    manifest.fps = *overrides.fps;
  }
  return manifest;
}

std::vector<NamedInput> DatasetInputs(const std::filesystem::path& dataset,
                                      const DatasetManifest& manifest) {
  return {{dataset, "the dataset"},
          {manifest.images_dir, "the dataset's images"},
          {manifest.video_path, "the dataset's video"},
          {manifest.camera_path, "the camera calibration"},
          {manifest.gain_mask_path, "the gain mask"},
          {manifest.groundtruth_path, "the dataset's ground truth"}};
}

std::string ManifestName(const DatasetManifest& manifest) {
  return manifest.manifest_path.empty() ? std::string("dataset") : manifest.manifest_path.string();
}

double RequireInnerRadius(const DatasetManifest& manifest) {
  if (!manifest.inner_radius_m) {
    throw InputError(
        ManifestName(manifest) +
        ": the pipe radius is unknown: set key 'pipe.inner_radius_m' or pass --radius M");
  }
  return *manifest.inner_radius_m;
}

}  // namespace pipescope
