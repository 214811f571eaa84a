#include "pipescope/pipeline/dense_vo.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <optional>

#include "pipescope/estimation/predicted_stretch_bridging.h"
#include "pipescope/image/gain_mask.h"
#include "pipescope/io/image_source.h"
#include "pipescope/mapping/image_mosaic.h"
#include "pipescope/mapping/unrolled_mosaic_pass.h"
#include "pipescope/util/error.h"
#include "pipescope/util/progress.h"
#include "pipescope/util/timer.h"

namespace pipescope {
namespace {

double RequireReferenceScale(const DatasetManifest& manifest) {
  if (!manifest.reference_scale_px_per_m || !(*manifest.reference_scale_px_per_m > 0.0)) {
    throw InputError(ManifestName(manifest) +
                     ": reference_scale_px_per_m is missing; the dense methods need the "
                     "reference scale (000 §3.3): measure it with `pipescope refscale ... "
                     "--write dataset.yaml`");
  }
  return *manifest.reference_scale_px_per_m;
}

// Second pass of dense-unrolled: the frames on the unrolled wall at their estimated poses, one
// every `spacing_cells` of travel.
void BuildUnrolledMosaic(const DatasetManifest& manifest, const Camera& camera,
                         const cv::Mat& gain_mask, const UnrolledWallRegistration& unrolled,
                         double spacing_cells, DenseVoResult* result) {
  const UnrolledGrid& grid = unrolled.grid();
  std::map<std::size_t, Eigen::Isometry3d> poses;
  for (std::size_t k = 0; k < result->frames.size(); ++k) {
    poses[result->frames[k].index] = ToIsometry(result->trajectory[k]);
  }
  // The footprint reaches beyond the camera's h by up to the grid's length either way.
  const double reach = grid.size.width * grid.pixel_m + std::abs(grid.h0_m);
  UnrolledMosaicMap map = MosaicAtPoses(manifest, camera, gain_mask, poses, grid.radius_m,
                                        grid.pixel_m, reach, spacing_cells * grid.pixel_m);
  result->mosaic = std::move(map.image);
  result->mosaic_pixel_m = map.pixel_m;
  result->mosaic_origin_m = map.origin_m;
}

// 000 Algorithm 1 bounds the search by the maximum speed and the frame rate.
void SetSearchWindowFromSpeed(const DatasetManifest& manifest, double zeta,
                              DenseOdometerOptions* options) {
  if (!(manifest.fps > 0.0)) {
    throw InputError(ManifestName(manifest) +
                     ": max_speed_m_s needs the frame rate (fps) to bound the search window");
  }
  const double per_frame_px =
      *options->max_speed_m_s / manifest.fps * zeta / options->frames.downsample;
  const int along = static_cast<int>(std::ceil(per_frame_px)) + 2;
  const int across = std::max(2, along / 2);
  const bool along_image_x = options->mount.axis_along_pipe.find('x') != std::string::npos;
  options->registration.full_search.max_shift_x_px = along_image_x ? along : across;
  options->registration.full_search.max_shift_y_px = along_image_x ? across : along;
}

}  // namespace

DenseVoResult RunDenseVo(const DatasetManifest& manifest, const Camera& camera,
                         const DenseOdometerOptions& requested_options) {
  const double zeta = RequireReferenceScale(manifest);
  DenseOdometerOptions options = requested_options;
  if (options.max_speed_m_s) SetSearchWindowFromSpeed(manifest, zeta, &options);
  const bool on_unrolled_wall = options.method == DenseMethod::kUnrolled;
  const double radius =
      on_unrolled_wall ? RequireInnerRadius(manifest) : manifest.inner_radius_m.value_or(0.0);
  double wall_distance = 0.0;
  try {
    wall_distance = StartWallDistance(camera, zeta, radius);
  } catch (const InputError& error) {
    throw InputError(ManifestName(manifest) + ": " + error.what());
  }
  const cv::Mat gain_mask =
      manifest.gain_mask_path.empty() ? cv::Mat() : ReadGainMask(manifest.gain_mask_path);
  DenseOdometer odometer(camera, gain_mask, zeta, radius, options);
  DenseVoResult result;
  // Without the radius StartWallDistance gives 0; the planar methods' scale is f / zeta.
  result.wall_distance =
      MakeWallDistanceStatement(camera, options.mount, radius,
                                radius > 0.0 ? wall_distance : CentralFocalLengthPx(camera) / zeta,
                                "reference_scale_px_per_m", odometer.measures_cross_section());
  ImageMosaic image_mosaic(options.mosaic_spacing_px);
  ImageSourceOptions source_options{camera.Width(), camera.Height()};
  source_options.native_depth = true;  // the preparation converts in its first pass
  auto source = ImageSource::Open(manifest, source_options);
  ProgressBar progress(DenseMethodName(options.method), source->FrameCount());
  Timer timer;
  const ThreadCpuTimer cpu_timer;
  std::optional<StageClock<>> reading(std::in_place);
  while (std::optional<Frame> frame = source->Next()) {
    reading->AddTo(&result.stage_times, "reading");
    DenseOdometerStep step = odometer.Step(*frame);
    if (step.failed_pair) ++result.failed_pairs;
    if (options.build_mosaic && !on_unrolled_wall) {
      image_mosaic.Add(step.mosaic_frame, step.content_offset);
    }
    result.trajectory.push_back(ToStampedPose(frame->timestamp, step.world_from_cam));
    result.frames.push_back(std::move(step.record));
    progress.Update(frame->index + 1);
    reading.emplace();
  }
  progress.Finish();
  result.registration_seconds = timer.ElapsedSeconds();
  result.loop_cpu_seconds = cpu_timer.ElapsedSeconds();
  result.stage_times.Merge(odometer.stage_times());
  result.cross_section_alignments = odometer.cross_section_alignments();
  result.cross_section_rejections = odometer.cross_section_rejections();
  result.cross_section_sigmas_m = odometer.cross_section_sigmas();
  result.cross_section_faint = odometer.cross_section_faint();
  result.cross_section_blurred_from = odometer.cross_section_blurred_from();
  const int aligned = result.cross_section_alignments + result.cross_section_rejections;
  if (odometer.measures_cross_section() && aligned > 0 &&
      2 * result.cross_section_alignments < aligned) {
    // Most key frames held the place of the one before: the run's scale rests on the start's.
    result.wall_distance.method_measures = false;
    result.cross_section_warning =
        "dense-unrolled measured the camera's place across the pipe at only " +
        std::to_string(result.cross_section_alignments) + " of " + std::to_string(aligned) +
        " key frames (" + std::to_string(result.cross_section_faint) +
        " too faint or noisy to align): its scale rests on the start's wall distance";
  }
  result.skipped_frames = source->skipped_frames();
  if (result.frames.empty()) {
    throw InputError(ManifestName(manifest) + ": no readable frames");
  }
  std::vector<FrameMeasurement> measurements;
  for (const DenseFrameRecord& frame : result.frames) {
    measurements.push_back({.predicted = !frame.failure.empty(), .became_key = frame.key_frame});
  }
  for (std::size_t k : BridgePredictedStretches(measurements, &result.trajectory)) {
    result.frames[k].bridged = true;
  }
  if (options.build_mosaic) {
    if (on_unrolled_wall) {
      BuildUnrolledMosaic(manifest, camera, gain_mask, *odometer.unrolled(),
                          options.mosaic_spacing_px, &result);
    } else {
      result.mosaic = image_mosaic.Render();
    }
  }
  return result;
}

}  // namespace pipescope
