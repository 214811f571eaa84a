#include "pipescope/pipeline/ekf_vo.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "pipescope/feature/guided_zncc.h"
#include "pipescope/image/gain_mask.h"
#include "pipescope/io/image_source.h"
#include "pipescope/pipeline/travel_direction.h"
#include "pipescope/util/error.h"
#include "pipescope/util/progress.h"
#include "pipescope/util/timer.h"

namespace pipescope {
namespace {

Eigen::Vector3d AxisInCamera(const std::string& name) {
  if (name == "z") return Eigen::Vector3d::UnitZ();
  if (name == "x") return Eigen::Vector3d::UnitX();
  if (name == "y") return Eigen::Vector3d::UnitY();
  throw InputError("axis_along_tube: unknown axis '" + name + "' (valid: auto, z, x, y)");
}

// The axis along the tube in the camera frame: the option's, or with "auto" the camera axis
// nearest its measured direction of travel (pipeline/travel_direction.h). Nearest, never the
// direction itself: a crawler that moves sideways as it starts travels off the pipe's axis (the
// held-out tube-bend run with 30 mm of wander went 33 degrees off its optical axis, measured
// within 1.1 degrees of the truth, while its pipe ran along the optical axis), and the
// measurement errs by up to 18 degrees on a narrow wall view.
Eigen::Vector3d ChooseAxisInCamera(const DatasetManifest& manifest, const Camera& camera,
                                   const cv::Mat& gain_mask, const cv::Mat& view,
                                   const EkfVoOptions& options, EkfVoResult* result) {
  std::string name = options.axis_along_tube;
  if (name == "auto") {
    KltTrackerOptions tracker_options = options.tracker;
    tracker_options.flat_field_sigma_px = 0.0;
    result->travel = MeasureTravelDirection(manifest, camera, gain_mask, view, tracker_options,
                                            TravelDirectionOptions{});
    const Eigen::Vector3d along = result->travel->direction.cwiseAbs();
    name = along.z() >= along.x() && along.z() >= along.y() ? "z"
           : along.x() >= along.y()                         ? "x"
                                                            : "y";
  }
  result->axis_along_tube = name;
  return AxisInCamera(name);
}

// The share of the gain mask's brightest below which a pixel counts as unlit: the frame there,
// divided by the mask, is mostly amplified noise.
constexpr double kMinLitShare = 0.05;
// A wall-looking camera's least look-ahead for a new section (EkfVoOptions::spawn_lookahead_radii).
constexpr double kWallViewLookaheadRadii = 2.0;
// The flat field's sigma looking down the tube, as an angle at the image centre
// (EkfVoOptions::flat_field_width_share): the lights' shading is a pattern over angles.
constexpr double kFlatFieldSigmaRad = 0.1;

cv::Mat PreparedGrey(const cv::Mat& grey, const cv::Mat& gain_mask) {
  return gain_mask.empty() ? grey : ApplyGainMask(grey, gain_mask);
}

// The sections' extents along the centreline: each runs from its junction with the one before
// to the junction with the one after (the ends: the run's first and last arc length).
void MeasureSections(const TubeCentreline& centreline, EkfVoResult* result) {
  for (std::size_t i = 0; i < result->sections.size(); ++i) {
    EkfSectionRecord& record = result->sections[i];
    record.start_arc_m =
        i == 0 ? 0.0
               : ArcLengthAlong(centreline,
                                SectionJunction(result->sections[i - 1].geometry, record.geometry));
  }
  for (std::size_t i = 0; i < result->sections.size(); ++i) {
    result->sections[i].end_arc_m =
        i + 1 < result->sections.size() ? result->sections[i + 1].start_arc_m : centreline.Length();
  }
}

}  // namespace

Eigen::Isometry3d TubeFrameFromWorld(const TubeSection& first_section,
                                     const Eigen::Vector3d& first_position,
                                     const Eigen::Vector3d& phi_zero) {
  const Eigen::Vector3d z = first_section.axis.normalized();
  Eigen::Vector3d x = phi_zero - phi_zero.dot(z) * z;
  if (x.norm() < 1e-6) x = z.unitOrthogonal();
  x.normalize();
  Eigen::Matrix3d world_from_tube;
  world_from_tube << x, z.cross(x), z;
  const Eigen::Vector3d origin =
      first_section.start + first_section.AxialCoordinate(first_position) * z;
  Eigen::Isometry3d tube_from_world = Eigen::Isometry3d::Identity();
  tube_from_world.linear() = world_from_tube.transpose();
  tube_from_world.translation() = -world_from_tube.transpose() * origin;
  return tube_from_world;
}

bool LooksDownTube(const Eigen::Vector3d& axis_in_camera) {
  return std::abs(axis_in_camera.z()) > std::sqrt(0.5);
}

EkfVoResult RunEkfVo(const DatasetManifest& manifest, const Camera& camera,
                     const EkfVoOptions& options) {
  const double radius = options.metric ? RequireInnerRadius(manifest) : 1.0;
  TubularEkfOptions filter_options = options.filter;
  if (!options.metric) filter_options.radius_prior_sigma = 0.0;
  const cv::Mat gain_mask =
      ReadDatasetGainMask(manifest.gain_mask_path, camera.Width(), camera.Height());

  EkfVoResult result;
  result.metric = options.metric;
  // Where the camera sees the lit wall: inside the model's field of view and where the gain mask
  // is at least kMinLitShare of its brightest. A lens's image circle can be narrower than the
  // model's reach (a 190-degree fisheye), and beyond it the gain correction multiplies noise.
  cv::Mat view = BearingTable(camera, camera.MaxAngle()).valid_mask().clone();
  if (!gain_mask.empty()) view.setTo(0, gain_mask < kMinLitShare);
  result.axis_in_camera = ChooseAxisInCamera(manifest, camera, gain_mask, view, options, &result);
  if (options.curvature_sigma_radii >= 0.0) {
    filter_options.curvature_sigma_radii = options.curvature_sigma_radii;
  } else if (!LooksDownTube(result.axis_in_camera)) {
    filter_options.curvature_sigma_radii = 0.0;
  }
  if (options.spawn_lookahead_radii >= 0.0) {
    filter_options.spawn_lookahead_radii = options.spawn_lookahead_radii;
  } else if (!LooksDownTube(result.axis_in_camera)) {
    filter_options.spawn_lookahead_radii = kWallViewLookaheadRadii;
  }
  KltTrackerOptions tracker_options = options.tracker;
  if (options.flat_field_width_share >= 0.0) {
    tracker_options.flat_field_sigma_px = options.flat_field_width_share * camera.Width();
  } else {
    tracker_options.flat_field_sigma_px = LooksDownTube(result.axis_in_camera)
                                              ? kFlatFieldSigmaRad * camera.PixelsPerRadianOnAxis()
                                              : 0.0;
  }
  result.chosen = {filter_options.curvature_sigma_radii, filter_options.spawn_lookahead_radii,
                   tracker_options.flat_field_sigma_px};
  KltTracker tracker(tracker_options);
  tracker.SetViewMask(view);
  std::optional<TubularEkf> filter;
  std::vector<Eigen::Isometry3d> world_poses;
  std::vector<std::size_t> pose_frames;  // index into result.frames of each pose
  double last_timestamp = 0.0;

  auto source = ImageSource::Open(manifest, {camera.Width(), camera.Height()});
  ProgressBar progress("ekf", source->FrameCount());
  Timer timer;
  const ProcessCpuTimer cpu_timer;
  while (true) {
    StageClock<> read_clock;
    std::optional<Frame> frame = source->Next();
    if (!frame) break;
    EkfFrameRecord record;
    record.index = frame->index;
    record.timestamp = frame->timestamp;
    record.name = frame->name;
    if (SaturatedFraction(frame->grey, options.saturation_level) > options.max_saturated_fraction) {
      record.failure = "saturated";
      result.frames.push_back(record);
      continue;
    }
    cv::Mat grey8;
    PreparedGrey(frame->grey, gain_mask).convertTo(grey8, CV_8U);
    read_clock.AddTo(&result.stage_times, "read");

    const StageClock<> track_clock;
    const std::vector<KltPair> pairs = tracker.Track(grey8);
    track_clock.AddTo(&result.stage_times, "track");
    const StageClock<> filter_clock;
    if (!filter) {
      filter.emplace(camera, Eigen::Isometry3d::Identity(), result.axis_in_camera, radius,
                     filter_options);
    } else {
      filter->Predict(frame->timestamp - last_timestamp);
      std::vector<TubularEkfMatch> matches;
      matches.reserve(pairs.size());
      for (const KltPair& pair : pairs) {
        TubularEkfMatch match;
        if (!camera.Unproject(Eigen::Vector2d(pair.previous.x, pair.previous.y),
                              &match.previous_bearing)) {
          continue;
        }
        match.pixel = Eigen::Vector2d(pair.current.x, pair.current.y);
        match.track_id = pair.track_id;
        matches.push_back(match);
      }
      record.tracked = static_cast<int>(matches.size());
      record.update = filter->Update(matches);
      if (!record.update.updated) {
        record.failure = "too few features agree with the filter (" +
                         std::to_string(record.update.used) + " of " +
                         std::to_string(record.update.matches) + ")";
      }
      spdlog::trace(
          "ekf: frame {}: {} features used, {} unplaced, {} gated, mean NIS {:.2f}, track drift "
          "{:.2f} px",
          frame->index, record.update.used, record.update.unplaced, record.update.gated,
          record.update.mean_nis, record.update.track_drift_px);
      if (record.update.spawned_section) {
        spdlog::debug("ekf: frame {}: new section {}: {}", frame->index,
                      filter->Sections().size() - 1, filter->Sections().back().reason);
      }
    }
    filter_clock.AddTo(&result.stage_times, "filter");
    last_timestamp = frame->timestamp;
    record.section = static_cast<int>(filter->Sections().size()) - 1;
    world_poses.push_back(filter->WorldFromCam());
    pose_frames.push_back(result.frames.size());
    result.frames.push_back(record);
    progress.Update(result.frames.size());
  }
  progress.Finish();
  result.skipped_frames = source->skipped_frames();
  result.odometry_seconds = timer.ElapsedSeconds();
  result.odometry_cpu_seconds = cpu_timer.ElapsedSeconds();
  if (!filter || world_poses.size() < 2) {
    throw RunFailedError("ekf: fewer than two usable frames, nothing to estimate");
  }

  // Output frame: the first section's (Z along the axis in the direction of travel).
  std::vector<TubeSection> world_sections;
  for (const TubularEkfSection& section : filter->Sections())
    world_sections.push_back(section.geometry);
  const Eigen::Vector3d first_position = world_poses.front().translation();
  const Eigen::Vector3d last_position = world_poses.back().translation();
  TubeSection first = world_sections.front();
  if ((last_position - first_position).dot(first.axis) < 0.0) first.axis = -first.axis;
  const Eigen::Vector3d camera_up = -Eigen::Vector3d::UnitY();  // world = the first camera frame
  const Eigen::Isometry3d tube_from_world = TubeFrameFromWorld(first, first_position, camera_up);
  for (std::size_t i = 0; i < world_sections.size(); ++i) {
    TubeSection section = i == 0 ? first : world_sections[i];
    section.start = tube_from_world * section.start;
    section.axis = tube_from_world.linear() * section.axis;
    section.curvature = tube_from_world.linear() * section.curvature;
    EkfSectionRecord record;
    record.geometry = section;
    record.first_frame =
        static_cast<int>(result
                             .frames[pose_frames[std::min<std::size_t>(
                                 filter->Sections()[i].first_frame, pose_frames.size() - 1)]]
                             .index);
    record.reason = filter->Sections()[i].reason;
    result.sections.push_back(record);
  }
  std::vector<TubeSection> sections;
  for (const EkfSectionRecord& record : result.sections) sections.push_back(record.geometry);
  result.centreline =
      BuildTubeCentreline(sections, tube_from_world * first_position,
                          tube_from_world * last_position, Eigen::Vector3d::UnitX());
  MeasureSections(result.centreline, &result);
  std::vector<Eigen::Isometry3d> poses;
  for (std::size_t i = 0; i < world_poses.size(); ++i) {
    const Eigen::Isometry3d pose = tube_from_world * world_poses[i];
    poses.push_back(pose);
    result.trajectory.push_back(ToStampedPose(result.frames[pose_frames[i]].timestamp, pose));
    result.frame_arc_m.push_back(ArcLengthAlong(result.centreline, pose.translation()));
  }

  if (options.build_mosaic) {
    const Timer mosaic_timer;
    // Frames in order of travel, at least the spacing apart.
    std::vector<std::size_t> chosen;  // indices into poses
    const double spacing = options.mosaic_frame_spacing_radii * sections.front().Radius();
    for (std::size_t i = 0; i < poses.size(); ++i) {
      if (chosen.empty() || result.frame_arc_m[i] >= result.frame_arc_m[chosen.back()] + spacing ||
          i + 1 == poses.size()) {
        chosen.push_back(i);
      }
    }
    const double begin =
        std::min(0.0, *std::min_element(result.frame_arc_m.begin(), result.frame_arc_m.end()));
    const double end =
        result.centreline.Length() + options.mosaic.ahead_radii * sections.back().Radius();
    TubeMosaic mosaic(result.centreline, begin, end, options.mosaic);
    std::vector<std::size_t> frame_indices;
    for (std::size_t i : chosen) frame_indices.push_back(result.frames[pose_frames[i]].index);
    ImageSourceOptions source_options{camera.Width(), camera.Height()};
    source_options.wanted = [&](std::size_t index) {
      return std::binary_search(frame_indices.begin(), frame_indices.end(), index);
    };
    auto again = ImageSource::Open(manifest, source_options);
    std::size_t next = 0;
    while (std::optional<Frame> frame = again->Next()) {
      while (next < chosen.size() &&
             result.frames[pose_frames[chosen[next]]].index < frame->index) {
        ++next;
      }
      if (next == chosen.size()) break;
      if (result.frames[pose_frames[chosen[next]]].index != frame->index) continue;
      mosaic.AddFrame(PreparedGrey(frame->grey, gain_mask), camera, poses[chosen[next]],
                      result.frame_arc_m[chosen[next]]);
    }
    result.mosaic = mosaic.image();
    result.mosaic_pixel_m = mosaic.pixel_m();
    result.mosaic_begin_m = mosaic.begin_m();
    result.mosaic_seconds = mosaic_timer.ElapsedSeconds();
  }
  return result;
}

}  // namespace pipescope
