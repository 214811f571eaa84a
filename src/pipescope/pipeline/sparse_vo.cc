#include "pipescope/pipeline/sparse_vo.h"

#include <cmath>
#include <future>
#include <map>
#include <optional>
#include <string>

#include "pipescope/image/gain_mask.h"
#include "pipescope/image/undistortion.h"
#include "pipescope/io/image_source.h"
#include "pipescope/mapping/unrolled_mosaic_pass.h"
#include "pipescope/util/error.h"
#include "pipescope/util/progress.h"
#include "pipescope/util/timer.h"

namespace pipescope {
namespace {

// The unrolled appearance map (000 Fig. 15/17) from the frames at their estimated poses.
void BuildMosaic(const DatasetManifest& manifest, const Camera& camera, const cv::Mat& gain_mask,
                 double radius_m, double pixel_m, double spacing_cells, SparseVoResult* result) {
  std::map<std::size_t, Eigen::Isometry3d> poses;
  std::size_t pose_index = 0;
  for (const SparseFrameRecord& record : result->frames) {
    if (!record.failure.empty()) continue;
    poses[record.index] = ToIsometry(result->trajectory[pose_index++]);
  }
  UnrolledMosaicMap map = MosaicAtPoses(manifest, camera, gain_mask, poses, radius_m, pixel_m,
                                        3.0 * radius_m, spacing_cells * pixel_m);
  result->mosaic = std::move(map.image);
  result->mosaic_pixel_m = map.pixel_m;
  result->mosaic_origin_m = map.origin_m;
}

void CheckOptions(const SparseVoOptions& options) {
  auto require = [](bool ok, const std::string& message) {
    if (!ok) throw InputError(message);
  };
  require(options.features.harris.grid_rows > 0 && options.features.harris.grid_cols > 0,
          "grid_rows, grid_cols: must be positive");
  require(options.features.harris.per_cell > 0, "per_cell: must be positive");
  require(options.odometer.initial_key_frames >= 2, "initial_key_frames: must be at least 2");
  require(options.odometer.refine_every >= 1, "refine_every: must be at least 1");
  require(options.odometer.window_every >= 1 &&
              options.odometer.window_size > options.odometer.window_fixed &&
              options.odometer.window_fixed >= 0,
          "window_size, window_every, window_fixed: need window_every >= 1 and window_size > "
          "window_fixed >= 0");
  require(options.min_correspondences >= 6, "min_correspondences: must be at least 6");
  require(options.wall_distance_m >= 0.0, "wall_distance_m: must not be negative");
  require(options.mosaic_pixel_m >= 0.0, "mosaic_pixel_m: must not be negative");
}

// Where a restart's frame at `timestamp` is, moving on along the axis at the speed of the
// localised frames of the last second before the loss.
Eigen::Isometry3d PredictedPose(const SparseOdometer& odometer,
                                const std::vector<SparseLocalisedFrame>& localised,
                                double timestamp) {
  const SparseLocalisedFrame& last = localised.back();
  std::size_t earlier = localised.size() - 1;
  while (earlier > 0 && last.timestamp - localised[earlier - 1].timestamp <= 1.0) --earlier;
  const Eigen::Isometry3d last_pose = odometer.PoseOf(last);
  double speed = 0.0;
  if (last.timestamp > localised[earlier].timestamp) {
    speed = (last_pose.translation().z() - odometer.PoseOf(localised[earlier]).translation().z()) /
            (last.timestamp - localised[earlier].timestamp);
  }
  Eigen::Isometry3d predicted = last_pose;
  predicted.translation().z() += speed * (timestamp - last.timestamp);
  return predicted;
}

}  // namespace

SparseVoResult RunSparseVo(const DatasetManifest& manifest, const Camera& camera,
                           const SparseVoOptions& options) {
  CheckOptions(options);
  const double radius = RequireInnerRadius(manifest);
  double wall_distance = options.wall_distance_m;
  const bool has_reference_scale =
      manifest.reference_scale_px_per_m && *manifest.reference_scale_px_per_m > 0.0;
  const bool start_measured = wall_distance > 0.0 || has_reference_scale;
  if (!(wall_distance > 0.0)) {
    wall_distance = has_reference_scale
                        ? CentralFocalLengthPx(camera) / *manifest.reference_scale_px_per_m
                        : radius;
  }
  if (wall_distance >= 2.0 * radius) {
    throw InputError(ManifestName(manifest) + ": the start camera would be " +
                     std::to_string(wall_distance) +
                     " m from the wall, beyond the pipe's diameter (wall_distance_m or "
                     "reference_scale_px_per_m)");
  }
  SparseVoResult result;
  result.wall_distance = MakeWallDistanceStatement(
      camera, options.mount, radius, wall_distance,
      options.wall_distance_m > 0.0 ? "wall_distance_m"
      : has_reference_scale         ? "reference_scale_px_per_m"
                                    : "none given: the camera taken to be on the pipe's axis",
      true);
  SparseVoOptions effective = options;
  effective.odometer.window.hold_first_cross_section =
      options.hold_measured_start && start_measured && !WallDistanceMeasured(result.wall_distance);
  const Eigen::Isometry3d start = MountedStartPose(options.mount, radius, wall_distance);
  // Without a measured start there is no place to anchor the cross-section to; where the view
  // measures the wall distance the images place the camera across the pipe themselves.
  if (!start_measured ||
      (WallDistanceMeasured(result.wall_distance) && !options.anchor_where_view_measures)) {
    effective.odometer.window.cross_section_anchor_sigma_m = 0.0;
  }
  effective.odometer.window.cross_section_anchor_xy = start.translation().head<2>();
  result.cross_section_anchor_sigma_m = effective.odometer.window.cross_section_anchor_sigma_m;
  const cv::Mat gain_mask =
      ReadDatasetGainMask(manifest.gain_mask_path, camera.Width(), camera.Height());

  const SparseFeatures features(camera, options.features);
  SparseOdometer odometer(camera, radius, start, effective.odometer, features, &result.stage_times);
  std::vector<SparseLocalisedFrame> localised;
  // The newest localised frame since the key frame: the next key frame when the span ends.
  struct Candidate {
    std::size_t frame_index;
    double timestamp;
    FrameFeatures features;
    PairMatches matches;
    double delta_h;
    std::size_t localised;
  };
  std::optional<Candidate> candidate;
  int failed_in_a_row = 0;
  // Inliers of the first frame localised against the current key frame (0: none yet): the
  // span's end is measured against them (KeyFrameOptions::min_correspondence_fraction).
  int span_start_inliers = 0;
  const auto note_span_start = [&](const PairMatches& matches) {
    const int inliers = static_cast<int>(matches.inliers.size());
    if (span_start_inliers == 0 && inliers >= options.min_correspondences) {
      span_start_inliers = inliers;
    }
  };
  // A frame that cannot be localised ends the span whatever its start had.
  const auto ends_span = [&](const PairMatches& matches) {
    return static_cast<int>(matches.inliers.size()) < options.min_correspondences ||
           features.EndsSpan(matches, span_start_inliers);
  };

  auto source = ImageSource::Open(manifest, {camera.Width(), camera.Height()});
  ProgressBar progress("sparse", source->FrameCount());
  Timer timer;
  const ProcessCpuTimer cpu_timer;
  // Reading, gain correction and feature extraction of the next frame run on a second thread
  // while this one matches and estimates (options.pipelined), one frame ahead.
  struct Loaded {
    Frame frame;
    double saturated = 0.0;
    FrameFeatures features;
    StageTimes times;  // reading and extraction, on the reader thread
  };
  auto load = [&]() -> std::optional<Loaded> {
    const StageClock<> read;
    std::optional<Frame> frame = source->Next();
    if (!frame) return std::nullopt;
    Loaded loaded;
    loaded.saturated = SaturatedFraction(frame->grey, options.saturation_level);
    if (loaded.saturated <= options.max_saturated_fraction) {
      const cv::Mat corrected =
          gain_mask.empty() ? frame->grey : ApplyGainMask(frame->grey, gain_mask);
      read.AddTo(&loaded.times, "read");
      loaded.features = features.Extract(corrected, &loaded.times);
    }
    loaded.frame = std::move(*frame);
    return loaded;
  };
  const std::launch policy = options.pipelined ? std::launch::async : std::launch::deferred;
  std::future<std::optional<Loaded>> next = std::async(policy, load);
  while (true) {
    std::optional<Loaded> loaded = next.get();
    if (!loaded) break;
    next = std::async(policy, load);
    result.stage_times.Merge(loaded->times);
    const Frame* frame = &loaded->frame;
    progress.Update(frame->index + 1);
    SparseFrameRecord record;
    record.index = frame->index;
    record.timestamp = frame->timestamp;
    record.name = frame->name;
    if (loaded->saturated > options.max_saturated_fraction) {
      record.failure = std::to_string(static_cast<int>(std::round(100.0 * loaded->saturated))) +
                       " % of the pixels saturated";
      result.frames.push_back(std::move(record));
      continue;
    }
    FrameFeatures frame_features = std::move(loaded->features);
    record.keypoints = static_cast<int>(frame_features.keypoints.size());
    if (odometer.Empty()) {
      if (static_cast<int>(frame_features.keypoints.size()) < options.min_correspondences) {
        record.failure = "too few keypoints to start";
        result.frames.push_back(std::move(record));
        continue;
      }
      odometer.StartAt(frame->index, frame->timestamp, std::move(frame_features));
      record.key_frame = true;
      localised.push_back({result.frames.size(), frame->timestamp, 0, 0.0, {}});
      result.frames.push_back(std::move(record));
      continue;
    }
    PairMatches matches =
        features.Match(odometer.CurrentFeatures(), frame_features, &result.stage_times);
    note_span_start(matches);
    if (ends_span(matches) && candidate) {
      // 000 §5.1: the frame before the one that ends the span becomes the key frame.
      odometer.Promote(candidate->frame_index, candidate->timestamp, std::move(candidate->features),
                       candidate->matches, candidate->delta_h);
      SparseLocalisedFrame& promoted = localised[candidate->localised];
      promoted.anchor = odometer.CurrentIndex();
      promoted.delta_h = 0.0;
      promoted.sightings.clear();
      result.frames[promoted.record].key_frame = true;
      candidate.reset();
      matches = features.Match(odometer.CurrentFeatures(), frame_features, &result.stage_times);
      span_start_inliers = 0;
      note_span_start(matches);  // the new span's first frame
    }
    SparseFeatures::AdoptRefinedPositions(matches, &frame_features);
    record.matches = matches.matched;
    record.inliers = static_cast<int>(matches.inliers.size());
    if (record.inliers < options.min_correspondences) {
      ++failed_in_a_row;
      if (options.restart_after_failed_frames > 0 &&
          failed_in_a_row >= options.restart_after_failed_frames && !localised.empty() &&
          record.keypoints >= options.min_correspondences) {
        odometer.RestartAt(frame->index, frame->timestamp, std::move(frame_features),
                           PredictedPose(odometer, localised, frame->timestamp));
        candidate.reset();
        span_start_inliers = 0;
        failed_in_a_row = 0;
        record.key_frame = true;
        record.predicted = true;
        localised.push_back(
            {result.frames.size(), frame->timestamp, odometer.CurrentIndex(), 0.0, {}});
        result.frames.push_back(std::move(record));
        continue;
      }
      record.failure =
          "only " + std::to_string(record.inliers) + " inlier correspondences to the key frame";
      result.frames.push_back(std::move(record));
      continue;
    }
    failed_in_a_row = 0;
    SparseLocalisedFrame frame_pose;
    frame_pose.record = result.frames.size();
    frame_pose.timestamp = frame->timestamp;
    frame_pose.anchor = odometer.CurrentIndex();
    frame_pose.delta_h = odometer.AxialStep(frame_features, matches, &frame_pose.sightings);
    if (ends_span(matches)) {
      // Already too far from the key frame it follows: it becomes a key frame itself.
      odometer.Promote(frame->index, frame->timestamp, std::move(frame_features), matches,
                       frame_pose.delta_h);
      span_start_inliers = 0;
      frame_pose.anchor = odometer.CurrentIndex();
      frame_pose.delta_h = 0.0;
      frame_pose.sightings.clear();
      record.key_frame = true;
    } else {
      candidate = Candidate{frame->index,       frame->timestamp,   std::move(frame_features),
                            std::move(matches), frame_pose.delta_h, localised.size()};
    }
    localised.push_back(std::move(frame_pose));
    result.frames.push_back(std::move(record));
  }
  progress.Finish();
  result.skipped_frames = source->skipped_frames();
  if (odometer.Empty()) {
    throw InputError(ManifestName(manifest) +
                     ": no usable frames (none readable with enough "
                     "keypoints)");
  }
  SparseOdometerOutput output = odometer.Finish(&localised);
  result.trajectory = std::move(output.trajectory);
  result.key_frames = std::move(output.key_frames);
  result.points = std::move(output.points);
  result.summary = odometer.summary();
  result.cross_section_excursion_m = CrossSectionExcursion(result.key_frames);
  result.odometry_seconds = timer.ElapsedSeconds();
  result.odometry_cpu_seconds = cpu_timer.ElapsedSeconds();
  if (options.build_mosaic) {
    double pixel_m = options.mosaic_pixel_m;
    if (!(pixel_m > 0.0)) pixel_m = wall_distance / CentralFocalLengthPx(camera);
    const Timer mosaic_timer;
    const ProcessCpuTimer mosaic_cpu_timer;
    BuildMosaic(manifest, camera, gain_mask, radius, pixel_m, options.mosaic_spacing_cells,
                &result);
    result.mosaic_seconds = mosaic_timer.ElapsedSeconds();
    result.mosaic_cpu_seconds = mosaic_cpu_timer.ElapsedSeconds();
  }
  return result;
}

}  // namespace pipescope
