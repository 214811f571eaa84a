#include "pipescope/camera/camera.h"

#include <ceres/jet.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "pipescope/util/error.h"

namespace pipescope {

const char* ProjectionStatusName(ProjectionStatus status) {
  switch (status) {
    case ProjectionStatus::kValid:
      return "valid";
    case ProjectionStatus::kBehindCamera:
      return "behind camera";
    case ProjectionStatus::kOutsideFieldOfView:
      return "outside field of view";
    case ProjectionStatus::kOutsideImage:
      return "outside image";
  }
  return "unknown";
}

Camera::Camera(CameraModelId model_id, int width, int height, std::vector<double> params)
    : model_id_(model_id), width_(width), height_(height), params_(std::move(params)) {
  const std::string name = CameraModelName(model_id_);
  const int num_params = CameraModelNumParams(model_id_);
  if (static_cast<int>(params_.size()) != num_params) {
    throw InputError("camera model '" + name + "' takes " + std::to_string(num_params) +
                     " params (" + CameraModelParamsInfo(model_id_) + "), got " +
                     std::to_string(params_.size()));
  }
  if (width_ <= 0 || height_ <= 0) {
    throw InputError("camera size must be positive, got " + std::to_string(width_) + "x" +
                     std::to_string(height_));
  }
  if (!CameraModelHasValidParams(model_id_, params_.data())) {
    throw InputError("camera model '" + name + "' params (" + CameraModelParamsInfo(model_id_) +
                     ") must be finite with a positive focal length (" +
                     (model_id_ == CameraModelId::kFisheyePoly ? "k1" : "fx, fy") + ")");
  }
  max_angle_ = CameraModelMaxAngle(model_id_, params_.data());
}

double ImageHalfAngleDeg(const Camera& camera) {
  double widest = 0.0;
  const int samples = 64;
  for (int i = 0; i <= samples; ++i) {
    const double u = (camera.Width() - 1) * i / double(samples);
    const double v = (camera.Height() - 1) * i / double(samples);
    for (const Eigen::Vector2d& pixel :
         {Eigen::Vector2d(u, 0), Eigen::Vector2d(u, camera.Height() - 1), Eigen::Vector2d(0, v),
          Eigen::Vector2d(camera.Width() - 1, v)}) {
      Eigen::Vector3d ray;
      if (!camera.Unproject(pixel, &ray)) continue;
      widest = std::max(widest, std::atan2(ray.head<2>().norm(), ray.z()));
    }
  }
  return widest * 180.0 / M_PI;
}

bool Camera::IsInImage(const Eigen::Vector2d& pixel) const {
  return pixel.x() >= -0.5 && pixel.x() <= width_ - 0.5 && pixel.y() >= -0.5 &&
         pixel.y() <= height_ - 0.5;
}

double Camera::PixelsPerRadianOnAxis() const {
  Eigen::Vector2d pixel;
  Eigen::Matrix<double, 2, 3> d_pixel_d_point;
  // Just off the axis, where a fisheye's radius over its angle is defined; at z = 1 the point's
  // x is the angle to first order.
  ProjectWithJacobians(Eigen::Vector3d(1e-6, 0.0, 1.0), &pixel, &d_pixel_d_point, nullptr);
  return d_pixel_d_point(0, 0);
}

ProjectionStatus Camera::CheckDirection(const Eigen::Vector3d& point_cam) const {
  if (point_cam.isZero(0.0)) return ProjectionStatus::kBehindCamera;
  if (CameraModelNeedsPositiveDepth(model_id_) && !(point_cam.z() > 0.0)) {
    return ProjectionStatus::kBehindCamera;
  }
  const double angle = std::atan2(point_cam.head<2>().norm(), point_cam.z());
  if (angle > max_angle_) return ProjectionStatus::kOutsideFieldOfView;
  return ProjectionStatus::kValid;
}

ProjectionStatus Camera::Project(const Eigen::Vector3d& point_cam, Eigen::Vector2d* pixel) const {
  const ProjectionStatus status = CheckDirection(point_cam);
  if (status == ProjectionStatus::kBehindCamera) return status;
  ProjectPoint(model_id_, params_.data(), point_cam.data(), pixel->data());
  if (status != ProjectionStatus::kValid) return status;
  return IsInImage(*pixel) ? ProjectionStatus::kValid : ProjectionStatus::kOutsideImage;
}

ProjectionStatus Camera::ProjectWithJacobians(const Eigen::Vector3d& point_cam,
                                              Eigen::Vector2d* pixel,
                                              Eigen::Matrix<double, 2, 3>* d_pixel_d_point,
                                              Eigen::MatrixXd* d_pixel_d_params) const {
  const ProjectionStatus status = CheckDirection(point_cam);
  if (status == ProjectionStatus::kBehindCamera) return status;

  // One Jet carries the derivatives for the 3 point coordinates then every parameter.
  using JetT = ceres::Jet<double, 3 + kMaxNumCameraParams>;
  const int num_params = NumParams();
  JetT point_jet[3];
  JetT params_jet[kMaxNumCameraParams];
  JetT pixel_jet[2];
  for (int i = 0; i < 3; ++i) point_jet[i] = JetT(point_cam[i], i);
  for (int j = 0; j < num_params; ++j) params_jet[j] = JetT(params_[j], 3 + j);
  ProjectPoint(model_id_, params_jet, point_jet, pixel_jet);

  for (int row = 0; row < 2; ++row) {
    (*pixel)[row] = pixel_jet[row].a;
    if (d_pixel_d_point != nullptr) {
      d_pixel_d_point->row(row) = pixel_jet[row].v.head<3>().transpose();
    }
  }
  if (d_pixel_d_params != nullptr) {
    d_pixel_d_params->resize(2, num_params);
    for (int row = 0; row < 2; ++row) {
      d_pixel_d_params->row(row) = pixel_jet[row].v.segment(3, num_params).transpose();
    }
  }
  if (status != ProjectionStatus::kValid) return status;
  return IsInImage(*pixel) ? ProjectionStatus::kValid : ProjectionStatus::kOutsideImage;
}

bool Camera::Unproject(const Eigen::Vector2d& pixel, Eigen::Vector3d* bearing) const {
  return UnprojectPixel(model_id_, params_.data(), max_angle_, pixel.data(), bearing->data());
}

double ReprojectionErrorPx(const Camera& camera, const Eigen::Isometry3d& cam_from_world,
                           const Eigen::Vector3d& point, const Eigen::Vector2d& observed) {
  Eigen::Vector2d pixel;
  const ProjectionStatus status = camera.Project(cam_from_world * point, &pixel);
  if (status == ProjectionStatus::kBehindCamera) return 1e9;
  return (pixel - observed).norm();
}

}  // namespace pipescope
