#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "pipescope/feature/region_harris.h"

namespace pipescope {

// Corners of the far wall: the dark middle of a forward fisheye's view, where the pipe's far
// wall and a junction's far side lie. The region Harris detector (001 §III-A) keeps the strongest
// corners of each quarter of the image, and the bright near wall wins them all, while a camera's
// turn is told from a shift across the pipe by what lies far away (docs/fisheye_mapping.md,
// "Turns confirmed or not"). Returns the strongest `count` corners inside `cone_mask` (non-zero
// where they may lie) less those within `duplicate_radius_px` of `existing`; `harris` gives the
// detector's window and floor (relative to the whole frame's strongest corner), its grid is
// ignored (the cone is one cell).
std::vector<cv::Point2f> FarWallCorners(const cv::Mat& grey, const cv::Mat& cone_mask,
                                        const RegionHarrisOptions& harris, int count,
                                        double duplicate_radius_px,
                                        const std::vector<cv::Point2f>& existing);

}  // namespace pipescope
