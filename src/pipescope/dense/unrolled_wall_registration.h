#pragma once

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pipescope/camera/camera.h"
#include "pipescope/image/wall_unrolling.h"

namespace pipescope {

// Registration on the unrolled wall (`dense-unrolled`, beyond 000): the planar methods assume a
// flat wall, which 000 §6.2.3 blames for its errors in the 6-inch pipe (foreshortening: the top
// and bottom of the image move slower than its middle). With the radius known, each frame is
// resampled onto the cylinder's surface (h, s = r phi) around the camera's footprint. Travel
// along the axis and roll about it are symmetries of the cylinder, so between two frames they
// are a pure translation of the unrolled images, whatever the lens and the camera's place in the
// cross-section: the translational registration is then exact, not an approximation.
//
// Because of that symmetry the resampling tables are the same for every pose of the form
// roll(phi) * travel(h) * start_pose: they are built once, for the start pose, and a frame's
// unrolled image is always in the coordinates of the camera's own footprint.
class UnrolledWallRegistration {
 public:
  // `start_world_from_cam`: the camera in the pipe frame (axis = Z); `pixel_m`: the unrolled
  // grid's cell, in metres on the wall; `downsample`: frames are box-filtered by this integer
  // factor before resampling, so cells of about the frame's pixel footprint do not alias.
  // The grid is the largest rectangle, centred on the optical axis's wall point, that the camera
  // sees whole, less `margin_cells` on each side. Throws InputError when the camera sees no wall.
  UnrolledWallRegistration(const Camera& camera, const Eigen::Isometry3d& start_world_from_cam,
                           double radius_m, double pixel_m, int downsample, int margin_cells = 2);

  // The unrolled image (CV_32F, grid-sized) of a gain-corrected frame box-filtered by the
  // `downsample` factor (DenseFramePreparation::CorrectAndDownsample).
  cv::Mat Unroll(const cv::Mat& filtered_frame) const;

  // Motion along the wall from the shift t between two unrolled images (next(x + t) =
  // reference(x)): the camera travelled -t.x cells along the axis and -t.y cells around it.
  double TravelFromShift(cv::Point2d shift) const { return -shift.x * grid_.pixel_m; }
  double RollFromShift(cv::Point2d shift) const {
    return -shift.y * grid_.pixel_m / grid_.radius_m;
  }

  const UnrolledGrid& grid() const { return grid_; }

 private:
  UnrolledGrid grid_;
  cv::Mat map_x_;  // in the downsampled frame's pixels
  cv::Mat map_y_;
};

// The pose `start_world_from_cam` moved `travel_m` along the pipe axis (Z) and rolled by
// `roll_rad` about it.
Eigen::Isometry3d PipeAxisMotion(const Eigen::Isometry3d& start_world_from_cam, double travel_m,
                                 double roll_rad);

}  // namespace pipescope
