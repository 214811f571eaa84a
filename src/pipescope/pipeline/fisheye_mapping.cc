#include "pipescope/pipeline/fisheye_mapping.h"

#include <algorithm>
#include <deque>
#include <exception>
#include <stdexcept>
#include <string>
#include <thread>

#include "pipescope/image/gain_mask.h"
#include "pipescope/image/settled_sections.h"
#include "pipescope/io/image_source.h"
#include "pipescope/io/trajectory.h"
#include "pipescope/util/progress.h"
#include "pipescope/util/stage_times.h"
#include "pipescope/util/timer.h"
#include "pipescope/util/work_queue.h"

namespace pipescope {
namespace {

// A tracked key frame handed to the odometry once its section is settled.
struct SectionedKeyframe {
  TrackedKeyframe tracked;
  KeyframeSection section;
};

void BuildSections(FisheyeMappingResult* result) {
  for (int k = 0; k < static_cast<int>(result->keyframes.size()); ++k) {
    FisheyeKeyframe& keyframe = result->keyframes[k];
    if (result->sections.empty() || result->sections.back().view_class != keyframe.filtered_class) {
      result->sections.push_back({k, k, keyframe.filtered_class});
    }
    result->sections.back().last_keyframe = k;
    keyframe.section = static_cast<int>(result->sections.size()) - 1;
  }
}

// Every frame's pose: key frames as estimated, frames between two key frames interpolated
// (linear position, slerp rotation) by timestamp, frames after the last key frame at its pose.
void InterpolateTrajectory(const std::vector<std::pair<int, double>>& frames,
                           FisheyeMappingResult* result) {
  std::size_t next = 0;
  const std::vector<FisheyeKeyframe>& keyframes = result->keyframes;
  for (const auto& [index, timestamp] : frames) {
    while (next < keyframes.size() && keyframes[next].frame_index < index) ++next;
    if (next < keyframes.size() && keyframes[next].frame_index == index) {
      result->trajectory.push_back(ToStampedPose(timestamp, keyframes[next].world_from_cam));
    } else if (next == 0) {
      continue;
    } else if (next == keyframes.size()) {
      result->trajectory.push_back(ToStampedPose(timestamp, keyframes.back().world_from_cam));
    } else {
      const FisheyeKeyframe& a = keyframes[next - 1];
      const FisheyeKeyframe& b = keyframes[next];
      const double s = (timestamp - a.timestamp) / std::max(1e-12, b.timestamp - a.timestamp);
      StampedPose pose;
      pose.timestamp = timestamp;
      pose.position = (1 - s) * a.world_from_cam.translation() + s * b.world_from_cam.translation();
      pose.rotation = Eigen::Quaterniond(a.world_from_cam.rotation())
                          .slerp(s, Eigen::Quaterniond(b.world_from_cam.rotation()))
                          .normalized();
      result->trajectory.push_back(pose);
    }
  }
}

// 001 §III-D after the odometry: each T between two straight sections adjusted with the two-
// cylinder model; the key frames after it and their points follow P_b, the T's points are the
// adjusted ones.
void AdjustTIntersections(const Camera& camera, const KeyframeOdometry& odometry,
                          const TIntersectionPassOptions& options, FisheyeMappingResult* result) {
  const StageClock<ProcessCpuTimer> clock;
  std::vector<int> section_of;
  std::vector<double> timestamps;
  std::vector<Eigen::Isometry3d> poses;
  for (int k = 0; k < odometry.KeyframeCount(); ++k) {
    section_of.push_back(result->keyframes[k].section);
    timestamps.push_back(result->keyframes[k].timestamp);
    poses.push_back(result->keyframes[k].world_from_cam);
  }
  std::vector<PipeViewClass> classes;
  for (const FisheyeSection& section : result->sections) classes.push_back(section.view_class);
  result->t_intersections =
      TIntersectionPass(camera, options)
          .Run(odometry, section_of, classes, timestamps, &poses, &result->points);
  for (int k = 0; k < odometry.KeyframeCount(); ++k) result->keyframes[k].world_from_cam = poses[k];
  clock.AddTo(&result->stage_times, "t_intersections");
}

}  // namespace

FisheyeMappingResult RunFisheyeMapping(const DatasetManifest& manifest, const Camera& camera,
                                       const FisheyeMappingOptions& options,
                                       const DenseMapPieceSink& dense_sink) {
  FisheyeMappingResult result;
  // The dense map reads the gain mask after the odometry: a bad one must stop the run now.
  if (options.dense_map.enabled) {
    ReadDatasetGainMask(manifest.gain_mask_path, camera.Width(), camera.Height());
  }
  FeatureTracker tracker(camera, options.tracking);
  const PipeViewClassifier classifier(camera, options.classification);
  std::vector<std::pair<int, double>> usable_frames;
  // The odometry runs on a second thread, key frame by key frame as their sections settle,
  // while the tracking goes on; it sees the same key frames in the same order as it would
  // after the tracking, so the poses do not depend on the threads' timing.
  SettledSections settled_sections(options.min_cluster_size);
  std::deque<TrackedKeyframe> unsettled;  // tracked key frames whose section is not settled
  std::vector<KeyframeSection> given_sections;
  WorkQueue<SectionedKeyframe> odometry_queue;
  KeyframeOdometry odometry(camera, options.odometry);
  std::exception_ptr odometry_error;
  StageTimes odometry_times;  // the odometry thread's own, merged after the join
  std::thread odometry_thread;
  const auto start_odometry = [&] {
    odometry_thread = std::thread([&] {
      try {
        while (std::optional<SectionedKeyframe> keyframe = odometry_queue.Pop()) {
          const StageClock<ThreadCpuTimer> clock;
          odometry.Add(std::move(keyframe->tracked), keyframe->section);
          clock.AddTo(&odometry_times, "odometry");
        }
      } catch (...) {
        odometry_error = std::current_exception();
      }
    });
  };
  if (options.overlap_odometry) start_odometry();
  // The thread is joined however this function ends.
  struct Joiner {
    WorkQueue<SectionedKeyframe>& queue;
    std::thread& thread;
    ~Joiner() {
      queue.Close();
      if (thread.joinable()) thread.join();
    }
  } joiner{odometry_queue, odometry_thread};
  const auto hand_over = [&](const std::vector<KeyframeSection>& sections) {
    for (const KeyframeSection& section : sections) {
      odometry_queue.Push({std::move(unsettled.front()), section});
      unsettled.pop_front();
      given_sections.push_back(section);
    }
  };

  auto source = ImageSource::Open(manifest, {camera.Width(), camera.Height()});
  ProgressBar progress("map", source->FrameCount());
  int failures_in_row = 0;
  while (std::optional<Frame> frame = source->Next()) {
    ++result.frames;
    const int index = static_cast<int>(frame->index);
    const StageClock<ProcessCpuTimer> tracking;
    TrackedKeyframe keyframe;
    const TrackingStep step = tracker.Track(frame->grey, index, &keyframe);
    tracking.AddTo(&result.stage_times, "tracking");
    progress.Update(static_cast<std::size_t>(result.frames));
    if (!step.usable) {
      result.failed_frames.push_back({index, frame->name, step.failure});
      if (++failures_in_row >= options.max_failures_in_row) {
        tracker.Reset();
        ++result.tracking_resets;
        failures_in_row = 0;
      }
      continue;
    }
    failures_in_row = 0;
    usable_frames.emplace_back(index, frame->timestamp);
    if (!step.keyframe) continue;
    const StageClock<ProcessCpuTimer> classification;
    const PipeViewMeasurement measurement = classifier.Classify(frame->grey);
    classification.AddTo(&result.stage_times, "classification");
    FisheyeKeyframe record;
    record.frame_index = index;
    record.timestamp = frame->timestamp;
    record.name = frame->name;
    record.initial_class = measurement.view_class;
    record.moment_ratio = measurement.moment_ratio;
    record.features = static_cast<int>(keyframe.features.size());
    record.matches_cosine = keyframe.matches_cosine;
    record.matches_guided = keyframe.matches_guided;
    record.median_flow_px = keyframe.median_flow_px;
    result.keyframes.push_back(record);
    unsettled.push_back(std::move(keyframe));
    hand_over(settled_sections.Add(measurement.view_class));
  }
  progress.Finish();
  result.unreadable_frames = source->skipped_frames();
  hand_over(settled_sections.Finish());
  const Timer wait_timer;
  if (!options.overlap_odometry) start_odometry();
  odometry_queue.Close();
  odometry_thread.join();
  result.stage_times.AddWall("odometry_wait", wait_timer.ElapsedSeconds());
  if (odometry_error) std::rethrow_exception(odometry_error);
  result.stage_times.Merge(odometry_times);

  std::vector<PipeViewClass> initial;
  for (const FisheyeKeyframe& keyframe : result.keyframes)
    initial.push_back(keyframe.initial_class);
  const std::vector<PipeViewClass> filtered =
      FilterPipeViewClasses(initial, options.min_cluster_size);
  for (std::size_t k = 0; k < filtered.size(); ++k)
    result.keyframes[k].filtered_class = filtered[k];
  BuildSections(&result);
  // The odometry must have seen the whole sequence's sections (SettledPipeViewClassCount).
  for (const KeyframeSection& given : given_sections) {
    const FisheyeSection& section = result.sections[given.section];
    if (result.keyframes[given.keyframe].section != given.section ||
        section.first_keyframe != given.first_keyframe ||
        (section.last_keyframe == given.keyframe) != given.last_in_section) {
      throw std::logic_error("key frame " + std::to_string(given.keyframe) +
                             ": the odometry saw another section than the filtered sequence's");
    }
  }
  for (int k = 0; k < odometry.KeyframeCount(); ++k) {
    FisheyeKeyframe& keyframe = result.keyframes[k];
    keyframe.world_from_cam = odometry.WorldFromCam(k);
    keyframe.points_used = odometry.StepRecord(k).points_used;
    keyframe.direction_rejected = odometry.StepRecord(k).direction_rejected;
    keyframe.stationary = odometry.StepRecord(k).stationary;
  }
  result.windows = odometry.windows();
  result.points = odometry.Points();
  // 001 §III-D: the T's adjustment uses the straight windows' radius, tau, robust cost and
  // outlier removal, so a --config that changes them changes both.
  TIntersectionPassOptions t_options = options.t_intersections;
  const StraightWindowOptions& window = options.odometry.window;
  t_options.adjustment.radius_m = window.radius_m;
  t_options.adjustment.tau = window.tau;
  t_options.adjustment.huber_px = window.huber_px;
  t_options.adjustment.stages = window.stages;
  t_options.adjustment.mad_factor = window.mad_factor;
  t_options.adjustment.min_mad_px = window.min_mad_px;
  AdjustTIntersections(camera, odometry, t_options, &result);
  {
    const StageClock<ProcessCpuTimer> clock;
    LoopClosureInput input{manifest, camera, odometry, window.radius_m, {}, {}, {}, {}};
    std::vector<Eigen::Isometry3d> poses;
    for (const FisheyeKeyframe& keyframe : result.keyframes) {
      input.frame_index.push_back(keyframe.frame_index);
      input.section_of.push_back(keyframe.section);
      poses.push_back(keyframe.world_from_cam);
    }
    for (const FisheyeSection& section : result.sections) {
      input.section_straight.push_back(section.view_class == PipeViewClass::kStraight);
    }
    input.step_confirmed.assign(result.keyframes.size(), false);
    for (const OdometryWindowRecord& window : result.windows) {
      if (!window.straight || !window.rejection.empty()) continue;
      for (int k = window.first_keyframe + 1; k <= window.last_keyframe; ++k) {
        input.step_confirmed[k] = true;
      }
    }
    result.loop_closure =
        CloseLoops(input, options.loop_closure, &poses, &result.t_intersections, &result.points);
    // The key frames still hold the poses from before the closure until the line after this.
    if (result.loop_closure.applied) {
      for (const FisheyeKeyframe& keyframe : result.keyframes) {
        result.keyframe_trajectory_before_loop_closure.push_back(
            ToStampedPose(keyframe.timestamp, keyframe.world_from_cam));
      }
    }
    for (std::size_t k = 0; k < poses.size(); ++k) result.keyframes[k].world_from_cam = poses[k];
    clock.AddTo(&result.stage_times, "loop_closure");
  }
  {
    const StageClock<ProcessCpuTimer> clock;
    MappedRoute route;
    for (const FisheyeKeyframe& keyframe : result.keyframes) {
      route.frame_index.push_back(keyframe.frame_index);
      route.section_of.push_back(keyframe.section);
      route.world_from_cam.push_back(keyframe.world_from_cam);
    }
    for (const FisheyeSection& section : result.sections) {
      route.section_straight.push_back(section.view_class == PipeViewClass::kStraight);
    }
    route.points = result.points;
    for (const TIntersectionRecord& t : result.t_intersections) {
      if (!t.rejection.empty()) continue;  // only an adjusted T joins its sections
      route.t_intersections.push_back(
          {t.section, t.geometry.centre, t.geometry.red_direction, t.geometry.blue_direction});
    }
    result.dense_map = BuildDenseMap(manifest, camera, route, options.odometry.window.radius_m,
                                     options.dense_map, dense_sink);
    clock.AddTo(&result.stage_times, "dense_map");
  }
  for (const FisheyeKeyframe& keyframe : result.keyframes) {
    result.keyframe_trajectory.push_back(
        ToStampedPose(keyframe.timestamp, keyframe.world_from_cam));
  }
  InterpolateTrajectory(usable_frames, &result);
  return result;
}

}  // namespace pipescope
