#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace pipescope {

// Helpers shared by the dense registration kernels (000 §4, 003 §2.3).

// Checks that `reference` and `next` form a registration pair (non-empty, one channel, the same
// size) and returns them as CV_32F in `reference_float` and `next_float` (no copy when they are
// CV_32F already). Throws InputError naming `what` (the calling method) otherwise.
void PrepareRegistrationPair(const cv::Mat& reference, const cv::Mat& next, const std::string& what,
                             cv::Mat* reference_float, cv::Mat* next_float);

// The reference pixels x of a pair of images of `size` whose x + shift falls inside the next
// image: the overlap the dense kernels compare at that shift (empty when there is none).
cv::Rect OverlapAtShift(cv::Size size, cv::Point shift);

// The number of levels of a Gaussian pyramid of an image of `size`: at most `max_levels`
// (at least 1, the image itself), each level half the size of the one below, the coarsest
// still at least `min_size_px` on its shorter side.
int NumPyramidLevels(cv::Size size, int max_levels, int min_size_px);

// A Gaussian pyramid by cv::pyrDown (5x5 binomial, then every other pixel): level 0 is `image`,
// level l + 1 has pixel i at level l's pixel 2 i, so a shift t at level 0 is t / 2^l at level l.
std::vector<cv::Mat> BuildGaussianPyramid(const cv::Mat& image, int num_levels);

}  // namespace pipescope
