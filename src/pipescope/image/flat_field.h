#pragma once

#include <opencv2/core.hpp>

namespace pipescope {

// `grey8` (CV_8U) divided by its Gaussian blur of `sigma_px`, at mid-grey (128), CV_8U; the
// frame itself for sigma_px <= 0. The lights move with the camera, so the wall's shading stays
// where it is in the image while the texture moves, and it drags Lucas-Kanade tracks towards
// zero flow; light times albedo divided by the light leaves the albedo. The sigma must exceed
// the texture's scale: the low frequencies it removes are lost to the tracker.
cv::Mat FlatFieldedGrey8(const cv::Mat& grey8, double sigma_px);

}  // namespace pipescope
