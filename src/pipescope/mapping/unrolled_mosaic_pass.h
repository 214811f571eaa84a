#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <map>
#include <opencv2/core.hpp>

#include "pipescope/camera/camera.h"
#include "pipescope/io/dataset.h"

namespace pipescope {

// The unrolled appearance map of a finished run (000 Fig. 15/17): the part of the wall seen.
struct UnrolledMosaicMap {
  cv::Mat image;  // CV_32F, NaN where unseen; rows along s = r phi, columns along h
  double pixel_m = 0.0;
  cv::Point2d origin_m;  // (h, s) of cell (0, 0)
};

// Second pass over the dataset's frames: each frame with a pose in `world_from_cam_by_frame`
// (frame index -> pose), gain-corrected by `gain_mask` (may be empty), enters the mean at that
// pose, one frame every `spacing_m` of travel (000's mosaics use frames 50 px apart). The grid
// spans the poses' travel and `reach_m` beyond either end.
UnrolledMosaicMap MosaicAtPoses(
    const DatasetManifest& manifest, const Camera& camera, const cv::Mat& gain_mask,
    const std::map<std::size_t, Eigen::Isometry3d>& world_from_cam_by_frame, double radius_m,
    double pixel_m, double reach_m, double spacing_m);

}  // namespace pipescope
