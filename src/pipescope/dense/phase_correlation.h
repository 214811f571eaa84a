#pragma once

#include <numbers>
#include <opencv2/core.hpp>

namespace pipescope {

// How the sub-pixel position of the correlation peak is found.
enum class PhasePeakMethod {
  kCentroid3x3,  // centroid of the positive part of the 3x3 neighbourhood (biased to the pixel)
  kParabolic,    // a parabola through the peak and its two neighbours, per axis
  // The maximum of the band-limited (DFT) interpolation of the correlation surface, by Newton's
  // method on c(t) = 1/M sum_k Q(k) exp(i 2 pi k.t / P) from the parabolic estimate: the limit
  // of Guizar-Sicairos et al.'s (2008) upsampled DFT without a grid, unbiased for a pure shift.
  kInterpolated,
};

struct PhaseCorrelationOptions {
  // A Hann window on both images before the transform (cv::createHanningWindow) suppresses the
  // cross-shaped artefacts of the images' borders, which the DFT treats as periodic.
  bool hann_window = true;
  PhasePeakMethod peak_method = PhasePeakMethod::kInterpolated;
  // Gaussian weighting of the normalised cross-power spectrum, exp(-|f|^2 / (2 s^2)) with f in
  // cycles per pixel and s = spectrum_sigma (0 = none, eq. 5 as written). Normalisation gives
  // every frequency the same weight, so the high frequencies, where the sensor noise outweighs
  // the wall's texture, add a noise floor to the whole surface and jitter the sub-pixel peak;
  // the weighting smooths the surface with a Gaussian of 1 / (2 pi s) pixels, which keeps a pure
  // shift's peak where it is. Not in 003. Measured on the blob texture of dense/testing.h with
  // noise sigma 1 at 160x120 and 256x192: RMS error 0.13 and 0.086 px without weighting, 0.011
  // and 0.009 px with s = 0.1 (0.08 is a little better on that smooth texture, but discards more
  // of a sharper one's detail).
  double spectrum_sigma = 0.1;
  // Two passes: the integer shift from a correlation on a coarse pyramid level (the coarsest of
  // up to 3 whose longer side is still coarse_level_min_size_px and shorter side 16 px: 80x60
  // for 160x120, 128x96 for 256x192, 160x120 for 640x480, 80x30 for the 160x60 band of a
  // 16-inch run; full resolution for smaller images), then the sub-pixel shift from a
  // correlation of the two images' overlap at that shift, each windowed there. A window fixed to
  // the frame pulls the peak towards zero shift (about 0.2 % of the shift); one that moves with
  // the content does not. Off: one correlation of the whole images (eq. 5-6 as written).
  bool refine_on_overlap = true;
  int coarse_level_min_size_px = 80;
  // Rotation by search (003 eq. 7): the reference is rotated about the image centre by each angle
  // of -max_rotation_rad ... max_rotation_rad in steps of rotation_step_rad (003: whole degrees
  // over +-10 degrees), and the angle with the highest peak wins. The search runs on the coarse
  // pyramid level (see coarse_level_min_size_px); a parabola through the best angle's
  // neighbours, then split_rotation_iterations corrections give the sub-step angle.
  bool estimate_rotation = false;
  double max_rotation_rad = 10.0 * std::numbers::pi / 180.0;
  // The search climbs from the step nearest the caller's prior to the nearest maximum of the peak
  // height, and scans the whole range only when that maximum is below rotation_search_min_peak
  // (measured on the coarse level). Off: the whole range every time, as 003 describes.
  bool rotation_from_prior = true;
  double rotation_search_min_peak = 0.2;
  double rotation_step_rad = 1.0 * std::numbers::pi / 180.0;
  // The angle is corrected this many times from the translations of the two halves of the
  // overlap (their difference across the halves' distance is the rotation left), each followed
  // by the translation again. Not in 003, whose parabolic refinement on the peak height is
  // coarser and costs more: bench/dense_bench's BM_Accuracy/phase_rotation (30 pairs within +-8
  // degrees), RMS angle error at 256x96 and 160x60: 0.076 and 0.27 degrees after the search
  // alone; 0.020 and 0.126 with one parabolic refinement at full resolution (three
  // correlations); 0.0094 and 0.027 with one split correction; 0.0090 and 0.023 with two
  // (docs/dense_vo.md).
  int split_rotation_iterations = 1;
};

struct PhaseCorrelationResult {
  // The motion maps a reference pixel x to the next pixel R(rotation) (x - c) + c + shift, with
  // c = ((width - 1) / 2, (height - 1) / 2) the image centre and R(a) = [cos a, -sin a; sin a,
  // cos a] in pixel coordinates (x right, y down: a positive angle turns clockwise on screen).
  // Without rotation this is next(x + shift) = reference(x), as in full_search.h.
  cv::Point2d shift;
  double rotation_rad = 0.0;
  // Height of the (weighted) normalised correlation peak of the last pass, 1 for identical
  // images, about 0.9 for a shifted noisy pair of the tests and below 0.2 for unrelated images:
  // the registration's confidence (003 §2.3: 1 for a perfect match).
  double peak = 0.0;
};

// Phase correlation (003 eq. 5-6): the normalised cross-power spectrum
//   Q = F{next} conj(F{reference}) / |F{next} conj(F{reference})|
// has the inverse transform c = F^-1{Q} with its maximum at the shift. (Eq. 5 writes the product
// the other way round, F{I_t-1} conj F{I_t}, whose peak is at minus the shift; we keep the
// library's sign convention.) Both images have their windowed mean removed, are multiplied by
// the window and zero-padded to a fast DFT size. Shifts are found modulo the padded size: at
// most half the image in each direction.
// Images: one channel, the same size, any depth. Throws InputError for a bad pair.
// `rotation_prior_rad`: the expected rotation, where the rotation search starts.
PhaseCorrelationResult RegisterPhaseCorrelation(const cv::Mat& reference, const cv::Mat& next,
                                                const PhaseCorrelationOptions& options = {},
                                                double rotation_prior_rad = 0.0);

}  // namespace pipescope
