#include "pipescope/pipeline/dense_vo.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "pipescope/dense/local_contrast.h"
#include "pipescope/image/gain_mask.h"
#include "pipescope/image/undistortion.h"
#include "pipescope/io/image_source.h"
#include "pipescope/mapping/image_mosaic.h"
#include "pipescope/mapping/unrolled_mosaic_pass.h"
#include "pipescope/pipeline/foreshortening.h"
#include "pipescope/pipeline/motion_prediction.h"
#include "pipescope/pipeline/unrolled_wall_registration.h"
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
                              DenseVoOptions* options) {
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

// The shift from the key frame has reached `fraction` of the frame along either axis.
bool ShiftReaches(const PairMotion& motion, double fraction, cv::Size frame) {
  return std::abs(motion.shift.x) >= fraction * frame.width ||
         std::abs(motion.shift.y) >= fraction * frame.height;
}

}  // namespace

bool FailedFrameBecomesKey(const PairMotion& motion, int failures_in_row, double shift_fraction,
                           cv::Size frame, const DenseVoOptions& options) {
  return failures_in_row >= options.key_frame_max_failures ||
         ShiftReaches(motion, shift_fraction + options.key_frame_wait_fraction, frame);
}

double KeyFrameFractionTarget(int n) {
  const double golden_fraction = 0.5 * (std::sqrt(5.0) - 1.0);
  const double value = n * golden_fraction;
  return value - std::floor(value);
}

double KeyFrameShiftFraction(DenseMethod method) {
  const bool integer_search =
      method == DenseMethod::kSad || method == DenseMethod::kSsd || method == DenseMethod::kZncc;
  return integer_search ? 0.4 : 0.1;
}

bool KeyFrameIsDue(const PairMotion& motion, double shift_fraction, cv::Size frame,
                   bool along_image_x, const DenseVoOptions& options, double carried_rounding_px,
                   std::optional<double> fraction_target) {
  if (!ShiftReaches(motion, shift_fraction, frame)) return false;
  if (shift_fraction <= 0.0 ||
      ShiftReaches(motion, shift_fraction + options.key_frame_wait_fraction, frame)) {
    return true;
  }
  // A whole-pixel shift kept by dense-hybrid carries up to half a pixel into every later frame
  // if it becomes the key frame; the next frame's refinement will most likely do.
  if (motion.integer_only) return false;
  if (!motion.rounding_residual) {
    if (!fraction_target || !(options.key_frame_fraction_tolerance_px > 0.0)) return true;
    const double along = along_image_x ? motion.shift.x : motion.shift.y;
    const double offset = along - std::floor(along) - *fraction_target;
    // The distance on the circle of fractions, in [0, 0.5].
    const double distance = std::abs(offset - std::round(offset));
    return distance <= options.key_frame_fraction_tolerance_px;
  }
  const cv::Point2d& residual = *motion.rounding_residual;
  const double carried_after = carried_rounding_px + (along_image_x ? residual.x : residual.y);
  return std::abs(carried_after) <=
         options.key_frame_max_rounding_px + std::max(0.0, std::abs(carried_rounding_px) - 0.5);
}

DenseVoResult RunDenseVo(const DatasetManifest& manifest, const Camera& camera,
                         const DenseVoOptions& requested_options) {
  const double zeta = RequireReferenceScale(manifest);
  DenseVoOptions options = requested_options;
  if (options.max_speed_m_s) SetSearchWindowFromSpeed(manifest, zeta, &options);
  const bool on_unrolled_wall = options.method == DenseMethod::kUnrolled;
  const double radius =
      on_unrolled_wall ? RequireInnerRadius(manifest) : manifest.inner_radius_m.value_or(0.0);
  // 000 §3.3: zeta is the image scale of the wall the camera faces, f / distance.
  const double wall_distance = radius > 0.0 ? CentralFocalLengthPx(camera) / zeta : 0.0;
  if (radius > 0.0 && wall_distance >= 2.0 * radius) {
    throw InputError(ManifestName(manifest) + ": reference_scale_px_per_m " + std::to_string(zeta) +
                     " puts the wall " + std::to_string(wall_distance) +
                     " m from the camera, beyond the pipe's diameter");
  }
  const Eigen::Isometry3d start = MountedStartPose(options.mount, radius, wall_distance);
  const cv::Mat gain_mask =
      manifest.gain_mask_path.empty() ? cv::Mat() : ReadGainMask(manifest.gain_mask_path);
  const double zeta_prepared = zeta / options.frames.downsample;
  const cv::Point2d principal_point =
      PreparedFramePrincipalPoint(camera, options.frames.downsample);
  const cv::Size prepared_size = PreparedFrameSize(camera, options.frames.downsample);
  // The band of the prepared frame the planar methods register.
  const bool along_image_x = options.mount.axis_along_pipe.find('x') != std::string::npos;
  cv::Rect band(cv::Point(0, 0), prepared_size);
  if (options.registration_band < 1.0) {
    if (!(options.registration_band > 0.0)) {
      throw InputError("registration_band: must be in (0, 1], got " +
                       std::to_string(options.registration_band));
    }
    const int across = along_image_x ? prepared_size.height : prepared_size.width;
    const int kept =
        std::max(16, static_cast<int>(std::lround(options.registration_band * across)));
    const double centre = along_image_x ? principal_point.y : principal_point.x;
    const int first = std::clamp(static_cast<int>(std::lround(centre - 0.5 * kept)), 0,
                                 std::max(0, across - kept));
    band = along_image_x ? cv::Rect(0, first, prepared_size.width, std::min(kept, across))
                         : cv::Rect(first, 0, std::min(kept, across), prepared_size.height);
  }
  const cv::Point2d band_principal_point = principal_point - cv::Point2d(band.tl());
  const cv::Point2d band_centre(0.5 * (band.width - 1), 0.5 * (band.height - 1));
  // The planar methods' frames resampled so that every line of the band moves at the same rate
  // along the pipe, axial_ratio * zeta (pipeline/foreshortening.h).
  double axial_ratio = 1.0;
  LineStretch stretch;
  if (!on_unrolled_wall && options.foreshortening_correction && radius > 0.0) {
    const int factor = options.frames.downsample;
    const std::vector<double> ratios = WallDepthRatios(
        start, radius, wall_distance, CentralFocalLengthPx(camera), PrincipalPoint(camera),
        along_image_x ? camera.Height() : camera.Width(), along_image_x);
    const AxialScaleEqualisation equalisation =
        EqualiseAxialScale(ratios, factor * (along_image_x ? band.y : band.x),
                           factor * (along_image_x ? band.height : band.width), along_image_x);
    axial_ratio = equalisation.axial_ratio;
    stretch = equalisation.stretch;
  }
  const DenseFramePreparation preparation(camera, gain_mask, options.frames, stretch);
  std::unique_ptr<UnrolledWallRegistration> unrolled;
  if (on_unrolled_wall) {
    // Cells of the prepared frames' pixel footprint on the wall the camera faces.
    unrolled = std::make_unique<UnrolledWallRegistration>(
        camera, start, radius, options.frames.downsample / zeta, options.frames.downsample,
        options.unrolled_margin_cells);
  }

  const DenseMethod registration_method =
      on_unrolled_wall ? options.unrolled_registration : options.method;
  PairRegistrationOptions registration = options.registration;
  // On the unrolled wall roll is a translation: phase correlation's rotation (003 eq. 7) would
  // only add noise.
  if (on_unrolled_wall) registration.phase.estimate_rotation = false;
  const bool gauss_newton = registration_method == DenseMethod::kLucasKanade ||
                            registration_method == DenseMethod::kHybrid;
  const bool presmooth = gauss_newton && options.presmooth_sigma_px > 0.0;
  const bool normalise_contrast = gauss_newton && options.contrast_normalisation_px > 0.0;
  if (normalise_contrast) {
    // The planar methods normalise the whole prepared frame and cut the band from it, so the
    // band's edges across the pipe see a two-sided filter; at the frame's ends along the pipe
    // (and around the unrolled frame) Gauss-Newton leaves out two sigmas, where the filter is
    // one-sided (dense/lucas_kanade.h, border_px).
    const double border = 2.0 * options.contrast_normalisation_px;
    const cv::Point2d border_px = on_unrolled_wall ? cv::Point2d(border, border)
                                  : along_image_x  ? cv::Point2d(border, 0.0)
                                                   : cv::Point2d(0.0, border);
    registration.lucas_kanade.border_px = border_px;
    registration.hybrid.refinement.border_px = border_px;
  }
  DenseVoResult result;
  ImageMosaic image_mosaic(options.mosaic_spacing_px);
  ImageSourceOptions source_options{camera.Width(), camera.Height()};
  source_options.native_depth = true;  // the preparation converts in its first pass
  auto source = ImageSource::Open(manifest, source_options);
  ProgressBar progress(DenseMethodName(options.method), source->FrameCount());
  // Each frame is registered to the current key frame, not to the one before: a registration's
  // sub-pixel bias then accrues once per key frame instead of once per frame (at 3 px a frame,
  // 0.01 px is 0.3 % of the travel). A frame becomes the key frame when its shift from the key
  // reaches key_frame_shift_fraction of the frame's extent, or its registration failed.
  struct KeyFrame {
    cv::Mat image;
    Eigen::Isometry3d pose;
    double travel = 0.0, roll = 0.0;  // dense-unrolled's state
    cv::Point2d content_offset;       // the image mosaic's
  };
  std::optional<KeyFrame> key;
  int failures_in_row = 0;  // on the current key frame
  // The integer searches' rounding residuals along the pipe, summed over the key frames so far:
  // the travel (in prepared pixels) their whole-pixel shifts have left out.
  double carried_rounding_px = 0.0;
  // The key frames so far, for the next one's target fraction (Gauss-Newton methods only:
  // phase correlation's error hardly depends on the fraction, and spreading it cost phase and
  // dense-unrolled a little, docs/dense_vo.md).
  int key_frames_chosen = 0;
  // The registered images' axis of travel: the unrolled grid's h runs along its columns.
  const bool travel_along_image_x = on_unrolled_wall || along_image_x;
  const auto fraction_target = [&]() -> std::optional<double> {
    if (!gauss_newton) return std::nullopt;
    return KeyFrameFractionTarget(key_frames_chosen + 1);
  };
  // The previous frame's motion from the key frame, and the good pairs' motion for the
  // constant-velocity prediction.
  cv::Point2d previous_shift(0.0, 0.0);
  double previous_rotation = 0.0;
  MotionPredictor predictor;
  double previous_timestamp = 0.0;
  const double key_shift_fraction =
      options.key_frame_shift_fraction.value_or(KeyFrameShiftFraction(options.method));
  Timer timer;
  Timer stage;
  const ThreadCpuTimer cpu_timer;
  while (std::optional<Frame> frame = source->Next()) {
    result.reading_seconds += stage.Lap();
    cv::Mat current, mosaic_frame;
    const double saturated = SaturatedFraction(frame->grey, options.saturation_level);
    if (on_unrolled_wall) {
      current = unrolled->Unroll(preparation.CorrectAndDownsample(frame->grey));
    } else {
      mosaic_frame = preparation.Prepare(frame->grey);
      current = mosaic_frame;
    }
    // Both filters write a new image: `current` may be the frame the image mosaic adds.
    if (presmooth) {
      cv::Mat smoothed;
      cv::GaussianBlur(current, smoothed, cv::Size(), options.presmooth_sigma_px);
      current = smoothed;
    }
    if (normalise_contrast) {
      current = NormaliseLocalContrast(current, options.contrast_normalisation_px);
    }
    if (!on_unrolled_wall) current = current(band);
    result.preparing_seconds += stage.Lap();
    DenseFrameRecord record;
    record.index = frame->index;
    record.timestamp = frame->timestamp;
    record.name = frame->name;
    Eigen::Isometry3d pose = start;
    double travel = 0.0, roll = 0.0;  // dense-unrolled's state
    cv::Point2d content_offset(0.0, 0.0);
    bool new_key = true;
    if (key) {
      const double dt = frame->timestamp - previous_timestamp;
      // The motion from the key frame at constant velocity.
      const ImageStep step = predictor.Predict(dt);
      const cv::Point2d predicted_shift = previous_shift + step.shift;
      const double predicted_rotation = previous_rotation + step.rotation_rad;
      PairMotion motion;
      if (saturated > options.max_saturated_fraction) {
        motion.failure = std::to_string(static_cast<int>(std::round(100.0 * saturated))) +
                         " % of the pixels saturated";
      } else {
        motion = RegisterPlanarPair(registration_method, key->image, current, registration,
                                    predicted_shift, predicted_rotation);
        const bool velocity_known = failures_in_row == 0 && predictor.Known();
        const double departure = cv::norm(motion.shift - predicted_shift);
        if (motion.failure.empty() && velocity_known &&
            options.max_departure_from_prediction_px > 0.0 &&
            departure > options.max_departure_from_prediction_px) {
          motion.failure = "shift " + std::to_string(static_cast<int>(std::round(departure))) +
                           " px from the constant-velocity prediction";
        }
      }
      if (motion.failure.empty()) {
        predictor.Add({motion.shift - previous_shift, motion.rotation_rad - previous_rotation}, dt);
      } else {
        ++result.failed_pairs;
        motion.shift = predicted_shift;
        motion.rotation_rad = predicted_rotation;
      }
      record.shift = motion.shift - previous_shift;
      record.rotation_rad = motion.rotation_rad - previous_rotation;
      record.correlation = motion.correlation;
      record.still = motion.still;
      record.integer_only = motion.integer_only;
      record.failure = motion.failure;
      if (on_unrolled_wall) {
        travel = key->travel + unrolled->TravelFromShift(motion.shift);
        roll = key->roll + unrolled->RollFromShift(motion.shift);
        pose = PipeAxisMotion(start, travel, roll);
      } else {
        cv::Point2d metric_shift = motion.shift;
        (along_image_x ? metric_shift.x : metric_shift.y) /= axial_ratio;
        pose = ApplyImageMotion(key->pose, metric_shift, motion.rotation_rad, zeta_prepared,
                                band_principal_point, band_centre);
      }
      content_offset = key->content_offset - motion.shift;
      failures_in_row = motion.failure.empty() ? 0 : failures_in_row + 1;
      new_key =
          motion.failure.empty()
              ? KeyFrameIsDue(motion, key_shift_fraction, current.size(), travel_along_image_x,
                              options, carried_rounding_px, fraction_target())
              : FailedFrameBecomesKey(motion, failures_in_row, key_shift_fraction, current.size(),
                                      options);
      if (new_key && motion.failure.empty() && motion.rounding_residual) {
        carried_rounding_px +=
            travel_along_image_x ? motion.rounding_residual->x : motion.rounding_residual->y;
      }
      previous_shift = motion.shift;
      previous_rotation = motion.rotation_rad;
    }
    record.key_frame = new_key;
    if (new_key) {
      ++key_frames_chosen;
      failures_in_row = 0;
      key = KeyFrame{current, pose, travel, roll, content_offset};
      previous_shift = cv::Point2d(0.0, 0.0);
      previous_rotation = 0.0;
    }
    if (options.build_mosaic && !on_unrolled_wall) image_mosaic.Add(mosaic_frame, content_offset);
    result.trajectory.push_back(ToStampedPose(frame->timestamp, pose));
    result.frames.push_back(std::move(record));
    previous_timestamp = frame->timestamp;
    progress.Update(frame->index + 1);
    result.registering_seconds += stage.Lap();
  }
  progress.Finish();
  result.registration_seconds = timer.ElapsedSeconds();
  result.loop_cpu_seconds = cpu_timer.ElapsedSeconds();
  result.skipped_frames = source->skipped_frames();
  if (result.frames.empty()) {
    throw InputError(ManifestName(manifest) + ": no readable frames");
  }
  if (options.build_mosaic) {
    if (on_unrolled_wall) {
      BuildUnrolledMosaic(manifest, camera, gain_mask, *unrolled, options.mosaic_spacing_px,
                          &result);
    } else {
      result.mosaic = image_mosaic.Render();
    }
  }
  return result;
}

}  // namespace pipescope
