#pragma once

#include <Eigen/Geometry>
#include <optional>

#include "pipescope/camera/camera.h"
#include "pipescope/image/undistortion.h"  // CentralFocalLengthPx
#include "pipescope/synthetic/simulation_config.h"

namespace pipescope {

// The camera a preset describes: its model, size, field of view and a mild lens distortion.
// pinhole-radtan: fx = fy = (width / 2) / tan(fov / 2), barrel distortion of `distortion` at the
// image corner; kannala-brandt: equidistant f = (width / 2) / (fov / 2) with k1 = -distortion / 10;
// fisheye-poly (001 eq. 1): r(theta) = k1 (theta - 0.2 distortion theta^3), with r(fov / 2) at
// half the width, or, for a fov of 180 degrees or more, at 0.49 of the height (a circular
// fisheye image, 001 Fig. 1c).
Camera MakeSimulatedCamera(const SimulationConfig& config);

// The camera's mounting on the robot body (body: z forward along the route, y down, x right).
// forward: the camera looks along the route. wall: principal axis along body y (the pipe's Y,
// towards the wall below), image x along the pipe axis, image y along the pipe's X (000 eq. 18).
// The camera sits mount_offset_m above the body centre (towards -y).
Eigen::Isometry3d BodyFromCam(const SimulationConfig& config);

// Pixels per metre on the wall at the image centre of the undistorted image for a wall-looking
// camera on the nominal path (000 §3.3): focal length over the distance to the wall. Empty for
// forward-looking cameras.
std::optional<double> ReferenceScalePxPerM(const SimulationConfig& config, const Camera& camera);

}  // namespace pipescope
