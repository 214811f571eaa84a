#pragma once

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include <vector>

#include "pipescope/camera/camera.h"

namespace pipescope {

struct CrossSectionAlignmentOptions {
  // Key-frame pixels sampled: every `stride_px`-th of the prepared (downsampled) frame in both
  // directions, inside `border_px` of its edges.
  int stride_px = 3;
  int border_px = 8;
  // Huber's loss beyond this many standard deviations of the residuals (their spread at the
  // start, 1.4826 MAD): highlights and the lights' changing sheen move with the camera, not
  // with the wall.
  double huber_sigmas = 2.0;
  // The offset across the pipe is held to the key frame's place with this standard deviation,
  // against residuals in units of their spread: the crawler's place changes little over one
  // key-frame step, and on faint texture one pair of views says little about it (0 = no prior).
  double offset_step_sigma_m = 0.0005;
  int max_iterations = 25;
  // Frames that are mostly noise are not to be trusted: the residuals' spread at the solution,
  // in units of the frames' local contrast, above this (steel-6in seed 1, medians over a run,
  // measured with every 2nd pixel: 0.39 with the preset's texture, 0.48 under a broad sheen, 0.98
  // at texture contrast 0.3 with noise 4, where the offsets found were off by up to 2.7 mm;
  // docs/conditions.md).
  double max_residual_sigma = 0.75;
  // The frames' local contrast normalisation (dense/local_contrast.h), prepared pixels.
  double contrast_normalisation_px = 8.0;
};

struct CrossSectionAlignment {
  bool converged = false;
  bool too_faint = false;  // CrossSectionAlignmentOptions::max_residual_sigma
  double travel_m = 0.0;  // the current camera's travel along the axis from the key frame's
  double roll_rad = 0.0;  // ... and its roll about the axis
  // How far both cameras lie from where the key frame's pose put them, across the pipe (the
  // pipe frame's X and Y): the change of the crawler's place in the cross-section that the
  // held pose did not know.
  Eigen::Vector2d offset_m = Eigen::Vector2d::Zero();
  int samples = 0;
  // The residuals' spread at the solution (1.4826 MAD), normalised grey levels.
  double residual_sigma = 0.0;
  // What the two frames alone fix of the offset (1 sigma of its less certain direction, from
  // the residuals' information with the prior left out; they are taken as independent, which
  // neighbouring samples are not quite).
  double offset_sigma_m = 0.0;
};

// The wall distance measured where the view can see it (issue 22, item 2; beyond 000): a key
// frame and a later frame aligned as wholes on the known cylinder. Every sampled key-frame pixel
// is cast onto the wall (radius `radius_m`, axis Z of the pipe frame) from the key camera, and
// projected into the current frame, whose pose is the key camera moved along the axis and
// rolled about it (travel and roll: the crawler's motion); the residual is the difference of
// the two frames' grey levels there, Huber's loss over them minimised by Ceres over travel,
// roll, and the offset across the pipe shared by both cameras (the crawler's place in the
// cross-section changes slowly against one key-frame step). The offset is observable because a
// wall point's depth depends on it: a camera nearer the wall sees its footprint move faster,
// and, in a wide view, unevenly across the curved wall (the parallax the planar methods cannot
// see). The key camera's orientation is held.
//
// Frames: prepared frames (the camera's pixels box-filtered by `downsample`), contrast-normalised
// (Normalised()) so that what is left of the lighting does not enter the residuals; CV_32F.
class CrossSectionAligner {
 public:
  CrossSectionAligner(const Camera& camera, double radius_m, int downsample,
                      const CrossSectionAlignmentOptions& options = {});

  // A prepared frame (DenseFramePreparation::CorrectAndDownsample) as Align() takes it, blurred
  // first by a Gaussian of `smooth_px` (0: not).
  cv::Mat Normalised(const cv::Mat& downsampled, double smooth_px = 0.0) const;

  // Starts from `travel_m`, `roll_rad` and `expected_offset_m`, where the prior holds the
  // offset (CrossSectionAlignmentOptions::offset_step_sigma_m). `key_world_from_cam`: the key
  // camera in the pipe frame.
  CrossSectionAlignment Align(const cv::Mat& key, const cv::Mat& current,
                              const Eigen::Isometry3d& key_world_from_cam, double travel_m,
                              double roll_rad,
                              const Eigen::Vector2d& expected_offset_m = Eigen::Vector2d::Zero()) const;

 private:
  // A sampled pixel of the prepared frame and its ray in the camera frame.
  struct SamplePixel {
    int x = 0, y = 0;
    Eigen::Vector3d bearing;
  };
  // The sampled pixels of a frame of `size` that the camera can unproject; the same for every
  // key frame, so made once (the unprojection is iterative for distorted models). The cache
  // makes Align() unsafe to call from two threads at once: one aligner per odometer.
  const std::vector<SamplePixel>& SamplePixels(const cv::Size& size) const;

  const Camera& camera_;
  double radius_m_;
  int downsample_;
  CrossSectionAlignmentOptions options_;
  mutable cv::Size sample_size_;
  mutable std::vector<SamplePixel> sample_pixels_;
};

}  // namespace pipescope
