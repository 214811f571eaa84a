// `pipescope undistort`: writes a dataset's frames rectified to the perspective image the dense
// methods use, so a user can look at them.
#include <spdlog/spdlog.h>

#include <cstdio>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "pipescope/camera/camera_io.h"
#include "pipescope/cli/subcommand.h"
#include "pipescope/image/undistortion.h"
#include "pipescope/io/dataset.h"
#include "pipescope/io/image_source.h"
#include "pipescope/util/atomic_file.h"
#include "pipescope/util/error.h"
#include "pipescope/util/output_paths.h"
#include "pipescope/util/progress.h"
#include "pipescope/util/staging_directory.h"

namespace pipescope {
namespace {

struct UndistortFlags {
  std::string dataset;
  std::string out;
  std::string camera;
};

int RunUndistort(const UndistortFlags& flags) {
  DatasetManifest manifest =
      OpenDataset(flags.dataset, {.camera_path = flags.camera, .inner_radius_m = {}, .fps = {}});
  RefuseOutputOverInputs(flags.out, "--out", DatasetInputs(flags.dataset, manifest));
  const Camera camera = ReadCamera(manifest.camera_path);
  const Undistorter undistorter(camera);
  auto source = ImageSource::Open(
      manifest, {.expected_width = camera.Width(), .expected_height = camera.Height()});
  StagingDirectory staging(flags.out, "--out", "dataset.yaml");
  std::filesystem::create_directories(staging.path() / "images");
  ProgressBar progress("undistort", source->FrameCount());
  int written = 0;
  std::string timestamps;  // of the frames written, so a skipped frame leaves its gap in time
  while (std::optional<Frame> frame = source->Next()) {
    cv::Mat rectified;
    undistorter.Apply(frame->grey).convertTo(rectified, CV_8U);
    char name[32];
    std::snprintf(name, sizeof(name), "%06zu.png", frame->index);
    if (!cv::imwrite((staging.path() / "images" / name).string(), rectified)) {
      throw InputError("cannot write " + (staging.path() / "images" / name).string());
    }
    char time[40];
    std::snprintf(time, sizeof(time), "%.9f\n", frame->timestamp);
    timestamps += time;
    progress.Update(++written);
  }
  progress.Finish();
  if (written == 0) throw InputError(flags.dataset + ": no readable frames");
  WriteCameraYaml(staging.path() / "camera.yaml", undistorter.rectified_camera());
  // The rectified folder is a dataset of its own, with the same timing, radius and ground truth.
  DatasetManifest rectified = manifest;
  rectified.name = manifest.name + " (undistorted)";
  rectified.camera_path = staging.path() / "camera.yaml";
  rectified.images_dir = staging.path() / "images";
  rectified.video_path.clear();
  rectified.gain_mask_path.clear();  // the mask is in the distorted image's coordinates
  WriteTextFileAtomically(staging.path() / "timestamps.txt", timestamps);
  rectified.timestamps_path = staging.path() / "timestamps.txt";
  if (!source->skipped_frames().empty()) {
    spdlog::warn("{} unreadable frames were left out; timestamps.txt keeps the others' times",
                 source->skipped_frames().size());
  }
  WriteDatasetManifest(staging.path() / "dataset.yaml", rectified);
  staging.Commit();
  spdlog::info("wrote {} rectified frames to {} (pinhole, f = {:.2f} px)", written, flags.out,
               CentralFocalLengthPx(camera));
  return kExitSuccess;
}

}  // namespace

SubcommandRunner SetupUndistortCommand(CLI::App* command) {
  auto flags = std::make_shared<UndistortFlags>();
  command->add_option("dataset", flags->dataset, "Dataset folder, manifest, or image folder")
      ->required();
  command->add_option("--out", flags->out, "Folder for the rectified frames")->required();
  command->add_option("--camera", flags->camera, "Calibration, for a plain image folder");
  return [flags] { return RunUndistort(*flags); };
}

}  // namespace pipescope
