#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "pipescope/camera/camera_models.h"

namespace pipescope {

// Why a point did or did not project to a usable pixel.
enum class ProjectionStatus {
  kValid,
  // z <= 0 for the perspective-type models, or the zero vector for any model; no pixel.
  kBehindCamera,
  // Angle from the optical axis beyond MaxAngle(); the pixel is still computed.
  kOutsideFieldOfView,
  // Projects, but outside [-0.5, width - 0.5] x [-0.5, height - 0.5]; the pixel is computed.
  kOutsideImage,
};

const char* ProjectionStatusName(ProjectionStatus status);

// A calibrated camera: a model, its parameters and the image size. Immutable; the model's
// maximum angle is computed once here because finding it costs a scan.
class Camera {
 public:
  // Throws InputError when the parameter count does not match the model, the size is not
  // positive, or the parameters are not finite or have non-positive focal lengths.
  Camera(CameraModelId model_id, int width, int height, std::vector<double> params);

  CameraModelId ModelId() const { return model_id_; }
  std::string ModelName() const { return CameraModelName(model_id_); }
  int Width() const { return width_; }
  int Height() const { return height_; }
  const std::vector<double>& Params() const { return params_; }
  int NumParams() const { return static_cast<int>(params_.size()); }
  // Largest valid angle from the optical axis, radians.
  double MaxAngle() const { return max_angle_; }

  // Whether the pixel lies on the image: pixel centres run from 0 to width - 1, so the image
  // covers [-0.5, width - 0.5] x [-0.5, height - 0.5].
  bool IsInImage(const Eigen::Vector2d& pixel) const;

  // Pixels per radian of view angle at the optical axis: fx for a pinhole or Kannala-Brandt
  // camera, k1 for 001's polynomial fisheye. Sets a pattern over angles (the lights' shading) in
  // pixels.
  double PixelsPerRadianOnAxis() const;

  ProjectionStatus Project(const Eigen::Vector3d& point_cam, Eigen::Vector2d* pixel) const;

  // Project() with the derivatives of the pixel with respect to the point (2x3) and to the
  // parameters (2 x NumParams()), from ceres::Jet through the templated projection. Either
  // Jacobian may be null; they are filled unless the status is kBehindCamera.
  ProjectionStatus ProjectWithJacobians(const Eigen::Vector3d& point_cam, Eigen::Vector2d* pixel,
                                        Eigen::Matrix<double, 2, 3>* d_pixel_d_point,
                                        Eigen::MatrixXd* d_pixel_d_params) const;

  // Unit bearing of the pixel; false when it lies beyond the model's maximum angle. Pixels off
  // the image are unprojected too.
  bool Unproject(const Eigen::Vector2d& pixel, Eigen::Vector3d* bearing) const;

 private:
  // kValid, kBehindCamera or kOutsideFieldOfView, from the direction alone.
  ProjectionStatus CheckDirection(const Eigen::Vector3d& point_cam) const;

  CameraModelId model_id_;
  int width_;
  int height_;
  std::vector<double> params_;
  double max_angle_;
};

// The widest angle, in degrees, between the optical axis and the ray of a pixel on the image's
// border (pixels outside a fisheye's image circle excluded): 35 for a 70-degree pinhole, 95 for
// a 190-degree fisheye. What a method needs to know of the set-up it is given.
double ImageHalfAngleDeg(const Camera& camera);

// Pixels between where a world point projects in a camera and where it was seen; 1e9 for a point
// behind the camera.
double ReprojectionErrorPx(const Camera& camera, const Eigen::Isometry3d& cam_from_world,
                           const Eigen::Vector3d& point, const Eigen::Vector2d& observed);

}  // namespace pipescope
