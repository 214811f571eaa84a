#pragma once

#include <filesystem>
#include <opencv2/core.hpp>

namespace pipescope {

// The 8-bit grey levels of a mosaic (CV_32F, NaN where empty) for viewing: a linear stretch
// mapping the 0.5th and 99.5th percentiles of the covered cells to 0 and 255 (saturating
// outside), so a few specular highlights do not squash the wall's contrast. Empty cells are
// 0; a mosaic whose covered cells are all equal is 128 there.
cv::Mat MosaicToGrey8(const cv::Mat& mosaic);

// MosaicToGrey8 written as an 8-bit PNG, atomically. Throws InputError naming the file when it
// cannot be written.
void WriteMosaicPng(const std::filesystem::path& path, const cv::Mat& mosaic);

}  // namespace pipescope
