#pragma once

#include <opencv2/core.hpp>

namespace pipescope {

// Local contrast normalisation for the Gauss-Newton registrations (dense-lk, dense-hybrid):
//   out = (I - G * I) / sqrt(G * (I - G * I)^2 + floor),
// G a Gaussian of `sigma_px`. Why: a pattern fixed in the frame (what gain correction leaves of
// the LEDs' specular sheen and of the lighting as the robot wobbles) multiplies the wall's
// texture by an envelope that does not move with it; the envelope's gradient enters Gauss-Newton's
// normal equations and pulls every shift towards zero (docs/dense_vo.md). Dividing by the local
// contrast removes any envelope that varies slowly over sigma_px, and an offset or gain
// exactly. `floor` is `floor_fraction` times the mean local variance, so that featureless areas
// (dark, saturated) are not blown up to noise of unit contrast.
// Input: one channel, any depth; output CV_32F of the same size. Throws InputError for an empty
// image, more than one channel or a sigma that is not positive.
cv::Mat NormaliseLocalContrast(const cv::Mat& image, double sigma_px, double floor_fraction = 0.01);

}  // namespace pipescope
