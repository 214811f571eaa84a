#pragma once

#include <filesystem>

#include "pipescope/camera/camera.h"

namespace pipescope {

// Reads a calibration, choosing the format by content (GUIDE §4):
//  - pipescope camera.yaml: `model`, `width`, `height`, `params`;
//  - OpenCV FileStorage (YAML starting with `%YAML:1.0`, or XML): `camera_matrix`,
//    `distortion_coefficients` (4: k1 k2 p1 p2, 5: k1 k2 p1 p2 k3, 8/12/14 only when the
//    rational, thin-prism and tilt terms are zero), `image_width`, `image_height`; a string
//    `distortion_model` or `camera_model` of `fisheye`/`equidistant` makes the 4 coefficients
//    Kannala-Brandt. Plain YAML with the same keys and {rows, cols, data} matrices (ROS
//    camera_info files) is read too;
//  - Kalibr camchain: `cam0` with `camera_model: pinhole`, `intrinsics`, `distortion_model`
//    (`radtan`, `equidistant` or `none`), `distortion_coeffs`, `resolution`.
// Throws InputError naming the file and the key at fault.
Camera ReadCamera(const std::filesystem::path& path);

// InputError naming `path` for a calibration no camera in a pipe can have: the principal point
// outside the image, a focal length beyond 0.05x-100x the image size, a lens model that cannot be
// inverted near the image centre, or an image that sees less than 5 degrees across. ReadCamera
// calls it; so does `calibrate` before it writes.
void CheckCameraIsPlausible(const std::filesystem::path& path, const Camera& camera);

// Writes a pipescope camera.yaml atomically, parameters at full precision.
void WriteCameraYaml(const std::filesystem::path& path, const Camera& camera);

}  // namespace pipescope
