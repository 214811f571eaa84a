#pragma once

#include <filesystem>
#include <opencv2/core.hpp>
#include <vector>

namespace pipescope {

// The gain mask of 000 §3.2: the mean of several images of a white card under the robot's own
// lights, smoothed with a Gaussian to remove noise, scaled so its maximum is 1 (CV_32F).
// Dividing a frame by it removes the lighting pattern and the lens vignetting.
cv::Mat BuildGainMask(const std::vector<cv::Mat>& white_card_images, double sigma_px);

// Gain correction (000 §3.2): `image` divided by the mask, in floating point with arbitrary
// range (CV_32F, one channel per input channel: colour channels share the mask). Mask values
// below 1 % of its maximum are clamped there, so the dark rim of a lens does not explode.
cv::Mat ApplyGainMask(const cv::Mat& image, const cv::Mat& mask);

// The factors ApplyGainMask multiplies a frame by: 1 / max(mask, 1 %) (CV_32F). Pipelines that
// fold the correction into another pass (a weighted block mean) take these once.
cv::Mat GainCorrectionFactors(const cv::Mat& mask);

// 16-bit PNG, 65535 = the mask's maximum; written atomically.
void WriteGainMask(const std::filesystem::path& path, const cv::Mat& mask);

// Reads a gain mask image (any depth) as CV_32F scaled to a maximum of 1. Throws InputError
// naming the file when it is missing, unreadable or zero.
cv::Mat ReadGainMask(const std::filesystem::path& path);

// A dataset's gain mask for frames of width x height: empty for an empty path (no mask), else
// ReadGainMask; throws InputError naming the file when its size differs from the frames'.
cv::Mat ReadDatasetGainMask(const std::filesystem::path& path, int width, int height);

}  // namespace pipescope
