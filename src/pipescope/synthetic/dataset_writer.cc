#include "pipescope/synthetic/dataset_writer.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdio>
#include <future>
#include <opencv2/imgcodecs.hpp>

#include "pipescope/camera/camera_io.h"
#include "pipescope/image/gain_mask.h"
#include "pipescope/io/dataset.h"
#include "pipescope/io/trajectory.h"
#include "pipescope/synthetic/checkerboard.h"
#include "pipescope/synthetic/scene_yaml.h"
#include "pipescope/synthetic/sensor.h"
#include "pipescope/synthetic/simulated_camera.h"
#include "pipescope/synthetic/simulation.h"
#include "pipescope/util/atomic_file.h"
#include "pipescope/util/error.h"
#include "pipescope/util/progress.h"
#include "pipescope/util/random.h"
#include "pipescope/util/staging_directory.h"
#include "pipescope/util/timer.h"

namespace pipescope {
namespace {

// Random streams of the sensor noise (the motion uses streams below 100).
constexpr std::uint64_t kWhiteCardNoiseStream = 101;
constexpr std::uint64_t kFrameNoiseStream = 102;
// Smoothing of the gain mask, as a fraction of the image width.
constexpr double kGainMaskSigmaFraction = 0.01;

void WritePng(const std::filesystem::path& path, const cv::Mat& image) {
  // Fast compression: the simulator is limited by rendering, not disk. Sensor noise leaves few
  // repeated strings, so Huffman coding alone beats level-1 LZ77 both ways (a steel-16in frame:
  // 8.7 instead of 11.4 ms, 160 instead of 185 kB).
  if (!cv::imwrite(path.string(), image,
                   {cv::IMWRITE_PNG_COMPRESSION, 1, cv::IMWRITE_PNG_STRATEGY,
                    cv::IMWRITE_PNG_STRATEGY_HUFFMAN_ONLY})) {
    throw InputError("cannot write " + path.string());
  }
}

std::string FrameName(int index) {
  char name[32];
  std::snprintf(name, sizeof(name), "%06d.png", index);
  return name;
}

std::string ConfigAsYaml(const SimulationConfig& config) {
  std::string text =
      "# pipescope simulate: every key of this dataset\npreset: " + config.preset + "\n";
  for (const ConfigKey& key : SimulationConfigKeys()) {
    text += std::string(key.name) + ": " + GetConfigValue(config, key.name) + "\n";
  }
  return text;
}

}  // namespace

std::string SimulationConfigYaml(const SimulationConfig& config) { return ConfigAsYaml(config); }

SimulationSummary SimulateDataset(const SimulationConfig& config,
                                  const std::filesystem::path& out) {
  // Calibration views have no pipe, route or lights: their own writer (issue 4).
  if (config.layout == "checkerboard") return SimulateCheckerboardDataset(config, out);
  StagingDirectory staging_folder(out, "--out", "simulation.yaml");
  const std::filesystem::path& staging = staging_folder.path();
  Timer timer;

  const Simulation simulation(config);
  const Camera& camera = simulation.camera();
  const Layout& layout = simulation.layout();

  std::filesystem::create_directories(staging / "images");
  std::filesystem::create_directories(staging / "white_card");
  // White cards along the route at nominal poses (000 §3.2); the brightest of the first sets
  // the exposure, as an operator would set the camera up.
  const cv::Mat vignetting = VignettingMap(camera, config.vignetting);
  SensorOptions sensor;
  sensor.noise_sigma = config.noise_sigma;
  sensor.electrons_per_grey_level = config.electrons_per_grey_level;
  std::vector<cv::Mat> white_cards;
  for (int k = 0; k < config.white_card_count; ++k) {
    const cv::Mat radiance = simulation.RenderWhiteCardRadiance(k);
    if (k == 0) {
      double max_value = 0.0;
      cv::minMaxLoc(radiance.mul(vignetting), nullptr, &max_value);
      if (!(max_value > 0.0)) throw std::runtime_error("the white card renders black");
      sensor.exposure = config.exposure_target / max_value;
    }
    white_cards.push_back(
        ApplySensor(radiance, vignetting, sensor, MixSeed(config.seed, kWhiteCardNoiseStream, k)));
    WritePng(staging / "white_card" / FrameName(k), white_cards.back());
  }
  WriteGainMask(staging / "gain_mask.png",
                BuildGainMask(white_cards, kGainMaskSigmaFraction * config.width));

  ProgressBar progress("simulate", config.frames);
  // The sensor and the PNG encoder run on one core; they take frame i while frame i + 1 renders
  // on all cores, so no core idles between frames. Each frame's noise has its own seed, so the
  // bytes do not depend on this overlap.
  std::future<void> pending;
  for (int i = 0; i < config.frames; ++i) {
    cv::Mat radiance = simulation.RenderFrameRadiance(i);
    if (pending.valid()) {
      pending.get();  // rethrows a write error
      progress.Update(i);
    }
    pending = std::async(std::launch::async, [&, i, radiance = std::move(radiance)] {
      WritePng(
          staging / "images" / FrameName(i),
          ApplySensor(radiance, vignetting, sensor, MixSeed(config.seed, kFrameNoiseStream, i)));
    });
  }
  pending.get();
  progress.Update(config.frames);
  progress.Finish();

  WriteTumTrajectory(staging / "groundtruth.tum", simulation.motion().Frames());
  WriteCameraYaml(staging / "camera.yaml", camera);
  RouteStart route_start;
  layout.route.Evaluate(layout.start_s_m, &route_start.position, &route_start.heading);
  WriteSceneYaml(staging / "scene.yaml", layout.scene, route_start);
  if (simulation.scale_target() != nullptr) {
    WriteScaleTargetYaml(staging / "target.yaml", *simulation.scale_target());
  }
  WriteTextFileAtomically(staging / "simulation.yaml", ConfigAsYaml(config));
  DatasetManifest manifest;
  manifest.name = config.preset.empty() ? out.filename().string() : config.preset;
  manifest.camera_path = staging / "camera.yaml";
  manifest.images_dir = staging / "images";
  manifest.fps = config.fps;
  manifest.inner_radius_m = config.radius_m;
  // The scene's gravity points along +Y (scene.h): 12 o'clock is -Y.
  manifest.pipe_up = Eigen::Vector3d(0.0, -1.0, 0.0);
  manifest.reference_scale_px_per_m = ReferenceScalePxPerM(config, camera);
  manifest.gain_mask_path = staging / "gain_mask.png";
  manifest.groundtruth_path = staging / "groundtruth.tum";
  manifest.scene_path = staging / "scene.yaml";
  WriteDatasetManifest(staging / "dataset.yaml", manifest);

  staging_folder.Commit();
  SimulationSummary summary;
  summary.frames = config.frames;
  summary.seconds = timer.ElapsedSeconds();
  summary.route_length_m = layout.route.Length();
  const Trajectory& frames = simulation.motion().Frames();
  for (std::size_t i = 1; i < frames.size(); ++i) {
    summary.travelled_m += (frames[i].position - frames[i - 1].position).norm();
  }
  if (!config.out_and_back && !frames.empty()) {
    const double reached = simulation.motion().ArcLength(frames.back().timestamp);
    summary.route_driven_m = reached - layout.start_s_m;
    summary.route_left_m = std::max(0.0, layout.start_s_m + layout.travel_m - reached);
  }
  return summary;
}

}  // namespace pipescope
