#pragma once

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pipescope/camera/camera.h"
#include "pipescope/mapping/tube_centreline.h"

namespace pipescope {

// 004 §3, dewarping: each cell of the unrolled tube (arc length along the centreline, r phi) is
// a point on the estimated section's wall; projected into a frame it takes that frame's grey
// value. Frames are added in the order of travel and a later frame overwrites what an earlier
// one painted, so each cell keeps the nearest view that saw it (the finest ground resolution).
// Through a bend the cells follow the chain of sections, so the mosaic stays continuous.
struct TubeMosaicOptions {
  // Cell size, metres; 0 = a hundredth of the radius.
  double pixel_m = 0.0;
  // Cells are painted from this far behind the camera to this far ahead (radii, along the
  // centreline).
  double behind_radii = 1.0;
  double ahead_radii = 4.0;
  // Pixels closer than this to the image border are not used.
  double margin_px = 2.0;
};

class TubeMosaic {
 public:
  // Covers arc lengths [begin_m, end_m] of the centreline; columns run along it, rows around the
  // tube from phi = 0 (the centreline's normal) towards -binormal: counter-clockwise looking in
  // the direction of travel (12, 9, 6, 3 o'clock with the normal up), so that the wall reads
  // as seen from inside, lettering the right way round.
  TubeMosaic(const TubeCentreline& centreline, double begin_m, double end_m,
             const TubeMosaicOptions& options);

  // Paints the cells the frame (CV_32F grey) sees from `world_from_cam`, whose foot on the
  // centreline lies at `camera_arc_m`.
  void AddFrame(const cv::Mat& grey, const Camera& camera, const Eigen::Isometry3d& world_from_cam,
                double camera_arc_m);

  // CV_32F, NaN where no frame saw the cell.
  const cv::Mat& image() const { return image_; }
  double pixel_m() const { return pixel_m_; }
  double begin_m() const { return begin_m_; }

 private:
  const TubeCentreline& centreline_;
  TubeMosaicOptions options_;
  double pixel_m_;
  double begin_m_;
  cv::Mat image_;
};

}  // namespace pipescope
