#pragma once

#include <Eigen/Geometry>
#include <deque>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "pipescope/camera/camera.h"
#include "pipescope/dense/dense_pair_registration.h"
#include "pipescope/dense/motion_prediction.h"
#include "pipescope/dense/unrolled_wall_registration.h"
#include "pipescope/estimation/cross_section_alignment.h"
#include "pipescope/geometry/camera_mount.h"
#include "pipescope/image/dense_frame_preparation.h"
#include "pipescope/io/image_source.h"
#include "pipescope/util/stage_times.h"

namespace pipescope {

// Dense monocular visual odometry for straight pipes (000 §4, 003 §2): every frame is
// registered to a key frame, the image motion is turned into metres with the reference scale
// and integrated from the start pose (000 eq. 18-19).
struct DenseOdometerOptions {
  DenseMethod method = DenseMethod::kHybrid;
  DenseFrameOptions frames;
  PairRegistrationOptions registration;
  // When set, the full-search window is the farthest the wall moves in one frame at this speed
  // (000 Algorithm 1's x_MAX along the pipe, half of it across), replacing the window of
  // `registration`.
  std::optional<double> max_speed_m_s;
  CameraMount mount;
  // The planar methods register only this fraction of the prepared frame across the pipe (rows
  // for a camera whose image x runs along the pipe), centred on the principal point. A
  // wall-looking camera sees the concave wall nearer towards the image's edges across the pipe
  // (000 §6.2.3), so those rows move faster than the centre's, and a translational fit over all
  // rows is biased by the mean of that variation; the bias grows with the square of the band.
  // 1 = the whole frame, as 000.
  double registration_band = 0.5;
  // Frames are registered to a key frame, which is renewed when a frame's shift from it reaches
  // this fraction of the registered frame's extent along either axis, or a registration fails:
  // a registration's sub-pixel bias, or an integer search's rounding, accrues once per key
  // frame, not once per frame. The full search's window is centred on the predicted shift, so
  // it need not cover the shift from the key. Unset: KeyFrameShiftFraction(method). At most
  // 0.45, below where phase correlation's shifts wrap. 0: every frame is registered to the one
  // before, as 000.
  std::optional<double> key_frame_shift_fraction;
  // The integer full searches (dense-sad, -ssd, -zncc) lose the fraction their rounding throws
  // away at every key frame; it is their error. Past key_frame_shift_fraction, such a frame
  // becomes the key frame only when its rounding residual along the pipe (dense/full_search.h),
  // added to what the earlier key frames' residuals sum to, is at most
  // key_frame_max_rounding_px, or once its shift has grown by key_frame_wait_fraction more of
  // the frame. Carrying the sum over (as error diffusion does) keeps the roundings from adding
  // up as a random walk over the key frames. Beyond 000; 0.5 px (or a wait of 0) turns it off,
  // and frame-to-frame registration (key_frame_shift_fraction 0) never waits.
  double key_frame_max_rounding_px = 0.15;
  double key_frame_wait_fraction = 0.1;
  // Gauss-Newton's registrations (dense-lk, dense-hybrid, and dense-unrolled registered by the
  // hybrid method) carry a small bias that depends on the fraction of a pixel in the shift
  // (pixel locking). When the speed varies, the key frames' fractions vary and the bias averages
  // out over them; at constant speed every key frame falls at nearly the same fraction and the
  // bias adds up (steel-16in at constant speed, dense-lk: between -0.11 and +0.04 % with the
  // key-frame spacing). With this on, past key_frame_shift_fraction such a frame becomes the key
  // frame only when the fraction of its shift along the pipe is within
  // key_frame_fraction_tolerance_px of the next of a sequence of targets spread evenly over the
  // pixel (the golden ratio's multiples), or once the key-frame wait is over. 0 = off.
  double key_frame_fraction_tolerance_px = 0.25;
  // A frame whose registration failed (blur, a dark or saturated frame) gets a predicted pose but
  // does not become the key frame: the next frame is registered to the same key, so one bad
  // frame costs only its own pose. The predicted frame becomes the key frame after this many
  // failures in a row (the key itself may be what no longer registers) or once its predicted
  // shift is past key_frame_shift_fraction + key_frame_wait_fraction. 1: every failed frame
  // becomes the key frame, as before session 9.
  int key_frame_max_failures = 3;
  // A registration that lands farther than this (prepared pixels, Euclidean) from the
  // constant-velocity prediction (dense/motion_prediction.h) fails, unless the pair before it
  // failed too: a crawler at 30 frames a second cannot change its image motion that much, and
  // such a shift is a false minimum, such as a painted marking's straight edge matched along
  // itself (steel-16in seed 3, dense-ssd: 29 px off the prediction, 43 mm of error). The
  // simulator's instant turnaround changes it by up to twice the speed:
  // 9.9 px on steel-16in seed 3, from its ground truth. 0 = off.
  double max_departure_from_prediction_px = 16.0;
  // When the dataset gives the pipe's radius, the planar methods' frames are resampled line by
  // line so that every line of the band moves at the same rate along the pipe, and that rate
  // converts the axial shift (image/foreshortening.h): the band's lines away from the
  // principal point see the concave wall nearer and would move more. Off: 000 eq. 19 as written.
  bool foreshortening_correction = true;
  // Gaussian smoothing of the registered frames (standard deviation, prepared pixels) for the
  // Gauss-Newton methods (dense-lk, dense-hybrid, and dense-unrolled registered by the hybrid
  // method). Off by default: it trades fine texture for what is left of the lighting pattern
  // after gain correction, which stays put in the image and pulls the shift towards zero
  // (measured: dense-unrolled -0.08 % -> -0.44 % of the distance at 1 px, docs/dense_vo.md).
  double presmooth_sigma_px = 0.0;
  // Local contrast normalisation of the registered frames for the same Gauss-Newton methods
  // (dense/local_contrast.h; the Gaussian's standard deviation in prepared pixels, 0 = off).
  // What gain correction leaves of the LEDs' sheen multiplies the texture by an envelope fixed
  // in the frame, whose gradient pulls Gauss-Newton towards zero motion; dividing by the local
  // contrast removes it (steel-6in seed 1, dense-lk: -0.046 % -> -0.001 %, floor +0.003 %;
  // docs/dense_vo.md).
  double contrast_normalisation_px = 8.0;
  // A frame with more saturated pixels than this is not registered (000 Fig. 12: highlights
  // pull the registration to zero motion); its motion is predicted.
  double max_saturated_fraction = 0.2;
  // Pixels of the raw frame at or above this 8-bit grey level count as saturated.
  double saturation_level = 250.0;
  // 000's image-space mosaic uses frames at least this far apart (appendix).
  double mosaic_spacing_px = 50.0;
  bool build_mosaic = true;
  // dense-unrolled: margin of the unrolled grid inside the camera's footprint, in cells.
  int unrolled_margin_cells = 2;
  // dense-unrolled registers the unrolled frames with this method: kPhase (phase correlation,
  // translation only: travel and roll are both translations there) or kHybrid. Phase by default:
  // its whitened spectrum gives little weight to what is left of the lighting after gain
  // correction, which stays put on the unrolled grid and pulls Gauss-Newton towards zero shift.
  // Measured against the hybrid method on the same frames, the error beyond what the robot's
  // drift and tilt cause fell from 0.035 % to 0.011 % (steel-6in, 8 seeds) and from 0.041 % to
  // 0.021 % (steel-16in, 4 seeds; docs/dense_vo.md).
  DenseMethod unrolled_registration = DenseMethod::kPhase;
  // dense-unrolled: at every key frame, the crawler's place in the cross-section is measured by
  // aligning the new key frame with an earlier one as wholes on the cylinder (issue 22, item 2;
  // estimation/cross_section_alignment.h), instead of being held where it started. "auto":
  // where the view sees the wall's curvature (estimation/wall_distance_observability.h); "on",
  // "off".
  std::string measure_cross_section = "auto";
  CrossSectionAlignmentOptions cross_section;
  // An alignment that moves the camera across the pipe by more than this share of the radius
  // in one key-frame step is not taken (the crawler cannot), nor one that did not converge,
  // nor one made while the frames are too faint: the median of the last eight alignments'
  // residual spreads above CrossSectionAlignmentOptions::max_residual_sigma (and before there
  // are eight).
  double max_cross_section_step = 0.03;
  // A new key frame is aligned with the latest earlier one at least this share of the unrolled
  // grid's length behind it (or the oldest of the last eight): the offset shows as the
  // parallax of the step, which grows with it.
  double cross_section_baseline_fraction = 0.33;
  // Once the frames are too faint to align at full detail, they are aligned blurred by a
  // Gaussian of this many prepared pixels for the rest of the run (the faintness check then
  // applies to the blurred frames); 0: the place is held instead. A wall whose fine texture is
  // below the noise may still have coarse texture: steel-6in at contrast 0.3 and noise 4, seeds
  // 1, 41, 43 and 47, ATE 11.4, 6.0, 10.0, 5.3 mm held against 2.6, 3.5, 2.0, 3.6 mm with 2 px
  // (docs/conditions.md).
  double cross_section_faint_smooth_px = 2.0;
};

// What happened to one frame.
struct DenseFrameRecord {
  std::size_t index = 0;
  double timestamp = 0.0;
  std::string name;
  // The image (or unrolled-grid) motion from the previous frame (the difference of the two
  // frames' registrations to their key frame).
  cv::Point2d shift;
  double rotation_rad = 0.0;  // phase only
  double correlation = 0.0;   // overlap ZNCC after registration
  bool still = false;
  bool integer_only = false;  // dense-hybrid kept the whole-pixel shift (PairMotion)
  bool key_frame = false;     // later frames were registered to this one
  // Why the registration failed and the motion was predicted at constant velocity; empty when
  // it did not (and for the first frame).
  std::string failure;
  // A failed frame whose pose was then interpolated between the measured frames around it
  // (estimation/predicted_stretch_bridging.h), not left at the prediction.
  bool bridged = false;
};

// The default key-frame spacing of a method, as a fraction of the registered frame (measured on
// the benchmark runs of docs/dense_vo.md): 0.4 for the integer full searches, whose error is one
// rounding per key frame (steel-6in dense-sad: 0.119 % at about 0.06, 0.023 % at 0.4); 0.1 for
// the sub-pixel methods, whose precision falls with the overlap (steel-16in phase: 3.0 % at 0.4,
// dense-hybrid 0.023 % against 0.003 %).
double KeyFrameShiftFraction(DenseMethod method);

// Whether a frame registered to the key frame without failure, with `motion` from it, becomes
// the next key frame: its shift has reached shift_fraction of `frame` along either axis and,
// for an integer search, its rounding residual along the pipe plus `carried_rounding_px` (the
// sum of the earlier key frames' residuals) is small enough, or the wait is over
// (DenseOdometerOptions' key_frame_max_rounding_px and key_frame_wait_fraction); a pair whose
// hybrid refinement was not used (PairMotion::integer_only) waits likewise. A carried sum beyond
// what one residual (at most 0.5 px) can cancel is accepted as reduced by
// key_frame_max_rounding_px. For a sub-pixel method, with `fraction_target` set (the odometry sets
// it for the Gauss-Newton methods), the fraction of its shift along the pipe must also be within
// key_frame_fraction_tolerance_px of the target (DenseOdometerOptions).
bool KeyFrameIsDue(const PairMotion& motion, double shift_fraction, cv::Size frame,
                   bool along_image_x, const DenseOdometerOptions& options,
                   double carried_rounding_px = 0.0,
                   std::optional<double> fraction_target = std::nullopt);

// The fraction of a pixel the n-th key frame of a Gauss-Newton method aims at: n times the golden
// ratio's fraction, modulo 1, spread evenly over [0, 1) for any count of key frames.
double KeyFrameFractionTarget(int n);

// Whether a frame whose registration failed, with its predicted `motion` from the key frame,
// becomes the next key frame (DenseOdometerOptions::key_frame_max_failures): after that many
// failures in a row on the current key, or once the predicted shift is past the key-frame wait.
bool FailedFrameBecomesKey(const PairMotion& motion, int failures_in_row, double shift_fraction,
                           cv::Size frame, const DenseOdometerOptions& options);

// The start camera's distance to the wall it faces, f / zeta (000 §3.3), 0 when the radius is
// unknown (0). Throws InputError naming reference_scale_px_per_m when that puts the wall beyond
// the pipe's diameter.
double StartWallDistance(const Camera& camera, double zeta_px_per_m, double radius_m);

// One frame's outcome: its record, its pose, and what the image-space mosaic takes of it.
struct DenseOdometerStep {
  DenseFrameRecord record;
  Eigen::Isometry3d world_from_cam = Eigen::Isometry3d::Identity();
  bool failed_pair = false;    // the registration failed and the motion was predicted
  cv::Mat mosaic_frame;        // the planar methods' prepared frame (empty for dense-unrolled)
  cv::Point2d content_offset;  // where the mosaic places it
};

// The dense odometry as a state machine over frames (000 §4, 003 §2, dense-unrolled ours):
// each Step() prepares a frame, registers it to the current key frame with the constant-velocity
// prediction, turns the motion into a pose and decides whether it becomes the next key frame.
// RunDenseVo (pipeline/dense_vo.h) drives it over a dataset.
class DenseOdometer {
 public:
  // `zeta_px_per_m`: the reference scale (000 §3.3) of the full-resolution perspective image;
  // `radius_m`: the pipe's inner radius, 0 when unknown (required by dense-unrolled);
  // `gain_mask` may be empty. Throws InputError naming the option or value at fault.
  DenseOdometer(const Camera& camera, const cv::Mat& gain_mask, double zeta_px_per_m,
                double radius_m, const DenseOdometerOptions& options);
  ~DenseOdometer();

  // `frame.grey`: the camera's size, any depth DenseFramePreparation takes. Frames must come in
  // order of their timestamps.
  DenseOdometerStep Step(const Frame& frame);

  // dense-unrolled's registration (its grid); null for the planar methods.
  const UnrolledWallRegistration* unrolled() const { return unrolled_.get(); }
  // Time spent "preparing" the frames and "registering" them, over all steps.
  const StageTimes& stage_times() const { return stage_times_; }
  // dense-unrolled with measure_cross_section: the key frames whose alignment was taken, and
  // those whose was not.
  bool measures_cross_section() const { return aligner_ != nullptr; }
  int cross_section_alignments() const { return cross_section_alignments_; }
  int cross_section_rejections() const { return cross_section_rejections_; }
  // ... of which, those made while the frames were too faint
  // (CrossSectionAlignmentOptions::max_residual_sigma).
  int cross_section_faint() const { return cross_section_faint_; }
  // Every alignment's CrossSectionAlignment::offset_sigma_m, in order.
  const std::vector<double>& cross_section_sigmas() const { return cross_section_sigmas_; }
  // The key frame (counted from 0) from which the frames were aligned blurred
  // (cross_section_faint_smooth_px); -1: never.
  int cross_section_blurred_from() const { return blurred_from_key_frame_; }

 private:
  struct KeyFrame {
    cv::Mat image;
    Eigen::Isometry3d pose;
    double travel = 0.0, roll = 0.0;  // dense-unrolled's state
    cv::Point2d content_offset;       // the image mosaic's
  };

  // The registered image of a frame: prepared (or unrolled), filtered, cut to the band.
  // dense-unrolled's `downsampled` frame (the gain-corrected block means) is kept.
  cv::Mat Registered(const cv::Mat& grey, cv::Mat* mosaic_frame, cv::Mat* downsampled) const;
  // measure_cross_section: one of the last key frames registered without failure, with its
  // pose.
  struct AlignedKey {
    cv::Mat downsampled;  // the prepared frame, before the aligner's filters
    Eigen::Isometry3d pose;
    double travel = 0.0, roll = 0.0;
    // CrossSectionAligner::Normalised(downsampled, normalised_smooth_px); empty until needed.
    cv::Mat normalised;
    double normalised_smooth_px = -1.0;
  };
  // The registered image of dense-unrolled's downsampled frame, or of the planar methods'
  // prepared frame.
  cv::Mat Filtered(cv::Mat current) const;
  // measure_cross_section, at a new key frame: the key frame's place across the pipe from its
  // alignment with an earlier one (cross_section_baseline_fraction); moves start_ there and
  // rebuilds the unrolled grid for it; false when the alignment is not taken. The key's travel and roll stay the
  // registration's (phase correlation on the unrolled wall measures them better than the
  // alignment, whose travel came out 0.15 % short from the true poses in its test; an offset
  // changes little over one key-frame step).
  // `key` is the new key frame (its pose is set by the caller afterwards).
  bool MeasureCrossSection(AlignedKey* key);
  // The key's frame as the aligner takes it now (blurred or not), normalised once and kept.
  const cv::Mat& AlignerFrame(AlignedKey* key) const;
  std::optional<double> FractionTarget() const;

  DenseOdometerOptions options_;
  double zeta_prepared_ = 0.0;
  bool on_unrolled_wall_ = false;
  bool along_image_x_ = true;
  // The registered images' axis of travel: the unrolled grid's h runs along its columns.
  bool travel_along_image_x_ = true;
  DenseMethod registration_method_ = DenseMethod::kHybrid;
  PairRegistrationOptions registration_;
  bool gauss_newton_ = false;
  bool presmooth_ = false;
  bool normalise_contrast_ = false;
  double key_shift_fraction_ = 0.0;
  // The pose at no travel and no roll; dense-unrolled with measure_cross_section moves it
  // across the pipe as the key frames measure the crawler's place.
  Eigen::Isometry3d start_ = Eigen::Isometry3d::Identity();
  const Camera& camera_;
  double radius_ = 0.0;
  double zeta_ = 0.0;
  std::unique_ptr<CrossSectionAligner> aligner_;
  // measure_cross_section: the last key frames registered without failure.
  std::deque<AlignedKey> aligned_keys_;
  int cross_section_alignments_ = 0;
  int cross_section_rejections_ = 0;  // including the faint ones
  int cross_section_faint_ = 0;
  std::vector<double> cross_section_sigmas_;
  std::deque<double> recent_residual_sigmas_;  // the last alignments' residual spreads
  // The frames have proved too faint at full detail: aligned blurred from here on.
  bool aligning_blurred_ = false;
  int blurred_from_key_frame_ = -1;
  cv::Rect band_;
  cv::Point2d band_principal_point_, band_centre_;
  double axial_ratio_ = 1.0;
  std::unique_ptr<DenseFramePreparation> preparation_;
  std::unique_ptr<UnrolledWallRegistration> unrolled_;

  // Each frame is registered to the current key frame, not to the one before: a registration's
  // sub-pixel bias then accrues once per key frame instead of once per frame (at 3 px a frame,
  // 0.01 px is 0.3 % of the travel).
  std::optional<KeyFrame> key_;
  int failures_in_row_ = 0;  // on the current key frame
  // The integer searches' rounding residuals along the pipe, summed over the key frames so far:
  // the travel (in prepared pixels) their whole-pixel shifts have left out.
  double carried_rounding_px_ = 0.0;
  // The key frames so far, for the next one's target fraction (Gauss-Newton methods only:
  // phase correlation's error hardly depends on the fraction, and spreading it cost phase and
  // dense-unrolled a little, docs/dense_vo.md).
  int key_frames_chosen_ = 0;
  // The previous frame's motion from the key frame, and the good pairs' motion for the
  // constant-velocity prediction.
  cv::Point2d previous_shift_{0.0, 0.0};
  double previous_rotation_ = 0.0;
  MotionPredictor predictor_;
  double previous_timestamp_ = 0.0;
  StageTimes stage_times_;
};

}  // namespace pipescope
