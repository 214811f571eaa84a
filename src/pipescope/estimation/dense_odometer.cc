#include "pipescope/estimation/dense_odometer.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <string>

#include "pipescope/dense/local_contrast.h"
#include "pipescope/estimation/wall_distance_observability.h"
#include "pipescope/image/foreshortening.h"
#include "pipescope/image/undistortion.h"
#include "pipescope/util/error.h"

namespace pipescope {
namespace {

// The shift from the key frame has reached `fraction` of the frame along either axis.
bool ShiftReaches(const PairMotion& motion, double fraction, cv::Size frame) {
  return std::abs(motion.shift.x) >= fraction * frame.width ||
         std::abs(motion.shift.y) >= fraction * frame.height;
}

}  // namespace

bool FailedFrameBecomesKey(const PairMotion& motion, int failures_in_row, double shift_fraction,
                           cv::Size frame, const DenseOdometerOptions& options) {
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
                   bool along_image_x, const DenseOdometerOptions& options,
                   double carried_rounding_px, std::optional<double> fraction_target) {
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

double StartWallDistance(const Camera& camera, double zeta, double radius) {
  // 000 §3.3: zeta is the image scale of the wall the camera faces, f / distance.
  const double wall_distance = radius > 0.0 ? CentralFocalLengthPx(camera) / zeta : 0.0;
  if (radius > 0.0 && wall_distance >= 2.0 * radius) {
    throw InputError("reference_scale_px_per_m " + std::to_string(zeta) + " puts the wall " +
                     std::to_string(wall_distance) +
                     " m from the camera, beyond the pipe's diameter");
  }
  return wall_distance;
}

DenseOdometer::DenseOdometer(const Camera& camera, const cv::Mat& gain_mask, double zeta,
                             double radius, const DenseOdometerOptions& options)
    : options_(options), camera_(camera), radius_(radius), zeta_(zeta) {
  on_unrolled_wall_ = options_.method == DenseMethod::kUnrolled;
  if (on_unrolled_wall_ && !(radius > 0.0)) {
    throw InputError("dense-unrolled needs the pipe's inner radius (pipe.inner_radius_m)");
  }
  const double wall_distance = StartWallDistance(camera, zeta, radius);
  start_ = MountedStartPose(options_.mount, radius, wall_distance);
  zeta_prepared_ = zeta / options_.frames.downsample;
  const cv::Point2d principal_point =
      PreparedFramePrincipalPoint(camera, options_.frames.downsample);
  const cv::Size prepared_size = PreparedFrameSize(camera, options_.frames.downsample);
  // The band of the prepared frame the planar methods register.
  along_image_x_ = options_.mount.axis_along_pipe.find('x') != std::string::npos;
  band_ = cv::Rect(cv::Point(0, 0), prepared_size);
  if (options_.registration_band < 1.0) {
    if (!(options_.registration_band > 0.0)) {
      throw InputError("registration_band: must be in (0, 1], got " +
                       std::to_string(options_.registration_band));
    }
    const int across = along_image_x_ ? prepared_size.height : prepared_size.width;
    const int kept =
        std::max(16, static_cast<int>(std::lround(options_.registration_band * across)));
    const double centre = along_image_x_ ? principal_point.y : principal_point.x;
    const int first = std::clamp(static_cast<int>(std::lround(centre - 0.5 * kept)), 0,
                                 std::max(0, across - kept));
    band_ = along_image_x_ ? cv::Rect(0, first, prepared_size.width, std::min(kept, across))
                           : cv::Rect(first, 0, std::min(kept, across), prepared_size.height);
  }
  band_principal_point_ = principal_point - cv::Point2d(band_.tl());
  band_centre_ = cv::Point2d(0.5 * (band_.width - 1), 0.5 * (band_.height - 1));
  // The planar methods' frames resampled so that every line of the band moves at the same rate
  // along the pipe, axial_ratio * zeta (image/foreshortening.h).
  LineStretch stretch;
  if (!on_unrolled_wall_ && options_.foreshortening_correction && radius > 0.0) {
    const int factor = options_.frames.downsample;
    const std::vector<double> ratios = WallDepthRatios(
        start_, radius, wall_distance, CentralFocalLengthPx(camera), PrincipalPoint(camera),
        along_image_x_ ? camera.Height() : camera.Width(), along_image_x_);
    const AxialScaleEqualisation equalisation =
        EqualiseAxialScale(ratios, factor * (along_image_x_ ? band_.y : band_.x),
                           factor * (along_image_x_ ? band_.height : band_.width), along_image_x_);
    axial_ratio_ = equalisation.axial_ratio;
    stretch = equalisation.stretch;
  }
  preparation_ =
      std::make_unique<DenseFramePreparation>(camera, gain_mask, options_.frames, stretch);
  if (on_unrolled_wall_) {
    // Cells of the prepared frames' pixel footprint on the wall the camera faces.
    unrolled_ = std::make_unique<UnrolledWallRegistration>(
        camera, start_, radius, options_.frames.downsample / zeta, options_.frames.downsample,
        options_.unrolled_margin_cells);
  }
  if (options_.measure_cross_section != "auto" && options_.measure_cross_section != "on" &&
      options_.measure_cross_section != "off") {
    throw InputError("measure_cross_section: must be auto, on or off, got '" +
                     options_.measure_cross_section + "'");
  }
  // Only dense-unrolled measures the place; the planar methods ignore the option.
  const bool measure = on_unrolled_wall_ &&
                       (options_.measure_cross_section == "on" ||
                        (options_.measure_cross_section == "auto" &&
                         AssessWallDistanceObservability(camera, start_, radius).observable));
  if (measure) {
    aligner_ = std::make_unique<CrossSectionAligner>(camera, radius, options_.frames.downsample,
                                                     options_.cross_section);
  }
  registration_method_ = on_unrolled_wall_ ? options_.unrolled_registration : options_.method;
  registration_ = options_.registration;
  // On the unrolled wall roll is a translation: phase correlation's rotation (003 eq. 7) would
  // only add noise.
  if (on_unrolled_wall_) registration_.phase.estimate_rotation = false;
  gauss_newton_ = registration_method_ == DenseMethod::kLucasKanade ||
                  registration_method_ == DenseMethod::kHybrid;
  presmooth_ = gauss_newton_ && options_.presmooth_sigma_px > 0.0;
  normalise_contrast_ = gauss_newton_ && options_.contrast_normalisation_px > 0.0;
  if (normalise_contrast_) {
    // The planar methods normalise the whole prepared frame and cut the band from it, so the
    // band's edges across the pipe see a two-sided filter; at the frame's ends along the pipe
    // (and around the unrolled frame) Gauss-Newton leaves out two sigmas, where the filter is
    // one-sided (dense/lucas_kanade.h, border_px).
    const double border = 2.0 * options_.contrast_normalisation_px;
    const cv::Point2d border_px = on_unrolled_wall_ ? cv::Point2d(border, border)
                                  : along_image_x_  ? cv::Point2d(border, 0.0)
                                                    : cv::Point2d(0.0, border);
    registration_.lucas_kanade.border_px = border_px;
    registration_.hybrid.refinement.border_px = border_px;
  }
  travel_along_image_x_ = on_unrolled_wall_ || along_image_x_;
  key_shift_fraction_ =
      options_.key_frame_shift_fraction.value_or(KeyFrameShiftFraction(options_.method));
}

DenseOdometer::~DenseOdometer() = default;

cv::Mat DenseOdometer::Registered(const cv::Mat& grey, cv::Mat* mosaic_frame,
                                  cv::Mat* downsampled) const {
  if (on_unrolled_wall_) {
    *downsampled = preparation_->CorrectAndDownsample(grey);
    return Filtered(unrolled_->Unroll(*downsampled));
  }
  *mosaic_frame = preparation_->Prepare(grey);
  return Filtered(*mosaic_frame);
}

cv::Mat DenseOdometer::Filtered(cv::Mat current) const {
  // Both filters write a new image: `current` may be the frame the image mosaic adds.
  if (presmooth_) {
    cv::Mat smoothed;
    cv::GaussianBlur(current, smoothed, cv::Size(), options_.presmooth_sigma_px);
    current = smoothed;
  }
  if (normalise_contrast_) {
    current = NormaliseLocalContrast(current, options_.contrast_normalisation_px);
  }
  if (!on_unrolled_wall_) current = current(band_);
  return current;
}

std::optional<double> DenseOdometer::FractionTarget() const {
  if (!gauss_newton_) return std::nullopt;
  return KeyFrameFractionTarget(key_frames_chosen_ + 1);
}

DenseOdometerStep DenseOdometer::Step(const Frame& frame) {
  const StageClock<> preparing;
  DenseOdometerStep step;
  const double saturated = SaturatedFraction(frame.grey, options_.saturation_level);
  cv::Mat downsampled;
  cv::Mat current = Registered(frame.grey, &step.mosaic_frame, &downsampled);
  preparing.AddTo(&stage_times_, "preparing");
  const StageClock<> registering;
  DenseFrameRecord& record = step.record;
  record.index = frame.index;
  record.timestamp = frame.timestamp;
  record.name = frame.name;
  Eigen::Isometry3d pose = start_;
  double travel = 0.0, roll = 0.0;  // dense-unrolled's state
  cv::Point2d content_offset(0.0, 0.0);
  bool new_key = true;
  if (key_) {
    const double dt = frame.timestamp - previous_timestamp_;
    // The motion from the key frame at constant velocity.
    const ImageStep predicted = predictor_.Predict(dt);
    const cv::Point2d predicted_shift = previous_shift_ + predicted.shift;
    const double predicted_rotation = previous_rotation_ + predicted.rotation_rad;
    PairMotion motion;
    if (saturated > options_.max_saturated_fraction) {
      motion.failure = std::to_string(static_cast<int>(std::round(100.0 * saturated))) +
                       " % of the pixels saturated";
    } else {
      motion = RegisterPlanarPair(registration_method_, key_->image, current, registration_,
                                  predicted_shift, predicted_rotation);
      const bool velocity_known = failures_in_row_ == 0 && predictor_.Known();
      const double departure = cv::norm(motion.shift - predicted_shift);
      if (motion.failure.empty() && velocity_known &&
          options_.max_departure_from_prediction_px > 0.0 &&
          departure > options_.max_departure_from_prediction_px) {
        motion.failure = "shift " + std::to_string(static_cast<int>(std::round(departure))) +
                         " px from the constant-velocity prediction";
      }
    }
    if (motion.failure.empty()) {
      predictor_.Add({motion.shift - previous_shift_, motion.rotation_rad - previous_rotation_},
                     dt);
    } else {
      step.failed_pair = true;
      motion.shift = predicted_shift;
      motion.rotation_rad = predicted_rotation;
    }
    record.shift = motion.shift - previous_shift_;
    record.rotation_rad = motion.rotation_rad - previous_rotation_;
    record.correlation = motion.correlation;
    record.still = motion.still;
    record.integer_only = motion.integer_only;
    record.failure = motion.failure;
    if (on_unrolled_wall_) {
      travel = key_->travel + unrolled_->TravelFromShift(motion.shift);
      roll = key_->roll + unrolled_->RollFromShift(motion.shift);
      pose = PipeAxisMotion(start_, travel, roll);
    } else {
      cv::Point2d metric_shift = motion.shift;
      (along_image_x_ ? metric_shift.x : metric_shift.y) /= axial_ratio_;
      pose = ApplyImageMotion(key_->pose, metric_shift, motion.rotation_rad, zeta_prepared_,
                              band_principal_point_, band_centre_);
    }
    content_offset = key_->content_offset - motion.shift;
    failures_in_row_ = motion.failure.empty() ? 0 : failures_in_row_ + 1;
    new_key =
        motion.failure.empty()
            ? KeyFrameIsDue(motion, key_shift_fraction_, current.size(), travel_along_image_x_,
                            options_, carried_rounding_px_, FractionTarget())
            : FailedFrameBecomesKey(motion, failures_in_row_, key_shift_fraction_, current.size(),
                                    options_);
    if (new_key && motion.failure.empty() && motion.rounding_residual) {
      carried_rounding_px_ +=
          travel_along_image_x_ ? motion.rounding_residual->x : motion.rounding_residual->y;
    }
    previous_shift_ = motion.shift;
    previous_rotation_ = motion.rotation_rad;
  }
  record.key_frame = new_key;
  if (new_key) {
    // A key frame after failed pairs keeps the pose it has and is no reference.
    if (aligner_ && record.failure.empty()) {
      const StageClock<> measuring;
      AlignedKey aligned{downsampled, pose, travel, roll, cv::Mat(), -1.0};
      if (!aligned_keys_.empty() && MeasureCrossSection(&aligned)) {
        pose = PipeAxisMotion(start_, travel, roll);
        current = Filtered(unrolled_->Unroll(downsampled));  // on the new grid
        aligned.pose = pose;
      }
      aligned_keys_.push_back(std::move(aligned));
      if (aligned_keys_.size() > 8) aligned_keys_.pop_front();
      measuring.AddTo(&stage_times_, "cross-section");
    }
    ++key_frames_chosen_;
    failures_in_row_ = 0;
    key_ = KeyFrame{current, pose, travel, roll, content_offset};
    previous_shift_ = cv::Point2d(0.0, 0.0);
    previous_rotation_ = 0.0;
  }
  previous_timestamp_ = frame.timestamp;
  step.world_from_cam = pose;
  step.content_offset = content_offset;
  registering.AddTo(&stage_times_, "registering");
  return step;
}

const cv::Mat& DenseOdometer::AlignerFrame(AlignedKey* key) const {
  const double smooth = aligning_blurred_ ? options_.cross_section_faint_smooth_px : 0.0;
  if (key->normalised.empty() || key->normalised_smooth_px != smooth) {
    key->normalised = aligner_->Normalised(key->downsampled, smooth);
    key->normalised_smooth_px = smooth;
  }
  return key->normalised;
}

bool DenseOdometer::MeasureCrossSection(AlignedKey* key) {
  const double travel = key->travel, roll = key->roll;
  const UnrolledGrid& grid = unrolled_->grid();
  const double baseline =
      options_.cross_section_baseline_fraction * grid.size.width * grid.pixel_m;
  AlignedKey* reference = &aligned_keys_.front();
  for (auto it = aligned_keys_.rbegin(); it != aligned_keys_.rend(); ++it) {
    if (std::abs(travel - it->travel) >= baseline) {
      reference = &*it;
      break;
    }
  }
  // Offsets in the pipe frame at the reference's roll; start_ is the pose at no roll.
  const Eigen::AngleAxisd to_reference(reference->roll, Eigen::Vector3d::UnitZ());
  const Eigen::Vector2d reference_place = reference->pose.translation().head<2>();
  const Eigen::Vector2d expected =
      (to_reference * start_.translation()).head<2>() - reference_place;
  const CrossSectionAlignment alignment = aligner_->Align(
      AlignerFrame(reference), AlignerFrame(key), reference->pose, travel - reference->travel,
      roll - reference->roll, expected);
  cross_section_sigmas_.push_back(alignment.offset_sigma_m);
  // Faint by the median of the last eight alignments' residual spreads, not this one's alone,
  // and until there are eight: on a wall too faint to measure, the odd alignment that passes is
  // as wrong as the rest (steel-6in seed 41 at texture contrast 0.3, noise 4: the first two
  // passed, and took the run from 0.08 % to 1.1 % off).
  constexpr std::size_t kRecent = 8;
  recent_residual_sigmas_.push_back(alignment.residual_sigma);
  if (recent_residual_sigmas_.size() > kRecent) recent_residual_sigmas_.pop_front();
  std::vector<double> recent(recent_residual_sigmas_.begin(), recent_residual_sigmas_.end());
  std::nth_element(recent.begin(), recent.begin() + recent.size() / 2, recent.end());
  if (recent.size() < kRecent) {
    ++cross_section_rejections_;
    return false;
  }
  if (recent[recent.size() / 2] > options_.cross_section.max_residual_sigma) {
    ++cross_section_faint_;
    ++cross_section_rejections_;
    if (!aligning_blurred_ && options_.cross_section_faint_smooth_px > 0.0) {
      // Try the coarse texture; eight blurred alignments must pass before one is taken.
      aligning_blurred_ = true;
      blurred_from_key_frame_ = key_frames_chosen_;
      recent_residual_sigmas_.clear();
    }
    return false;
  }
  if (!alignment.converged ||
      (alignment.offset_m - expected).norm() > options_.max_cross_section_step * radius_) {
    ++cross_section_rejections_;
    return false;
  }
  ++cross_section_alignments_;
  const Eigen::Vector2d place = reference_place + alignment.offset_m;
  start_.translation() = to_reference.inverse() *
                         Eigen::Vector3d(place.x(), place.y(), start_.translation().z());
  unrolled_ = std::make_unique<UnrolledWallRegistration>(
      camera_, start_, radius_, options_.frames.downsample / zeta_, options_.frames.downsample,
      options_.unrolled_margin_cells);
  return true;
}

}  // namespace pipescope
