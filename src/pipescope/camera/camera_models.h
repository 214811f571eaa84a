#pragma once

// Camera models as structs of static functions, in the manner of COLMAP's sensor/models.h: the
// projection is templated on the scalar type so that ceres::Jet passes through it and cost
// functions get exact derivatives; the inverse (unprojection) and the validity limit are plain
// double code in camera_models.cc.
//
// Camera frame: x right, y down, z forward. Pixel (0, 0) is the centre of the top-left pixel
// (GUIDE §3). Parameter orders are a file-format contract (GUIDE §4).

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace pipescope {

enum class CameraModelId { kPinholeRadtan = 0, kKannalaBrandt = 1, kFisheyePoly = 2 };

// The largest parameter count of any model (pinhole-radtan's), for fixed-size Jets and buffers.
inline constexpr int kMaxNumCameraParams = 9;

// Angles kept clear of the limits where a model degenerates: pi/2 for the perspective-type
// models (the point must stay in front, z > 0) and pi for fisheye-poly (the backward axis has
// no defined azimuth phi).
inline constexpr double kMaxAngleMargin = 1e-6;

// Below this squared tangent of the angle from the optical axis the projections switch to a
// Taylor expansion in the squared tangent, which is smooth at the axis, so neither the value nor
// the Jet derivative meets sqrt(0) or 0/0. The dropped terms are O(tan^4), below 1e-20.
inline constexpr double kAxisTan2Threshold = 1e-10;

// OpenCV's distortion model (cv::projectPoints with 5 coefficients):
//   x' = X/Z, y' = Y/Z, r^2 = x'^2 + y'^2,
//   x'' = x' (1 + k1 r^2 + k2 r^4 + k3 r^6) + 2 p1 x'y' + p2 (r^2 + 2 x'^2),
//   y'' = y' (1 + k1 r^2 + k2 r^4 + k3 r^6) + p1 (r^2 + 2 y'^2) + 2 p2 x'y',
//   u = fx x'' + cx, v = fy y'' + cy.
struct PinholeRadtanModel {
  static constexpr CameraModelId kId = CameraModelId::kPinholeRadtan;
  static constexpr int kNumParams = 9;
  static constexpr const char* kName = "pinhole-radtan";
  static constexpr const char* kParamsInfo = "fx, fy, cx, cy, k1, k2, p1, p2, k3";
  static constexpr bool kNeedsPositiveDepth = true;

  template <typename T>
  static void ProjectPoint(const T* params, const T* point_cam, T* pixel);
  // Newton's method on the 2x2 distortion map, started at the distorted point.
  static bool UnprojectPixel(const double* params, const double* pixel, double* bearing);
  static bool UnprojectPixel(const double* params, double max_angle, const double* pixel,
                             double* bearing);
  // Where the radial part r (1 + k1 r^2 + k2 r^4 + k3 r^6) stops increasing, r = tan(angle).
  static double MaxAngle(const double* params);
  static bool HasValidParams(const double* params);
};

// OpenCV's fisheye model (cv::fisheye::projectPoints, zero skew):
//   a = X/Z, b = Y/Z, r = sqrt(a^2 + b^2), theta = atan(r),
//   theta_d = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8),
//   u = fx (theta_d / r) a + cx, v = fy (theta_d / r) b + cy.
struct KannalaBrandtModel {
  static constexpr CameraModelId kId = CameraModelId::kKannalaBrandt;
  static constexpr int kNumParams = 8;
  static constexpr const char* kName = "kannala-brandt";
  static constexpr const char* kParamsInfo = "fx, fy, cx, cy, k1, k2, k3, k4";
  static constexpr bool kNeedsPositiveDepth = true;

  template <typename T>
  static void ProjectPoint(const T* params, const T* point_cam, T* pixel);
  // Newton's method on theta with a bisection safeguard.
  static bool UnprojectPixel(const double* params, const double* pixel, double* bearing);
  static bool UnprojectPixel(const double* params, double max_angle, const double* pixel,
                             double* bearing);
  // Where theta_d(theta) stops increasing, at most pi/2 - kMaxAngleMargin.
  static double MaxAngle(const double* params);
  static bool HasValidParams(const double* params);
};

// The polynomial fisheye of 001 eq. 1, a central projection through the unit view sphere:
//   theta = colatitude from +z, phi = atan2(Y, X),
//   r(theta) = k1 theta + k2 theta^3 + k3 theta^4 + k4 theta^5 pixels,
//   u = r cos(phi) + u0, v = r sin(phi) + v0.
// Points behind the image plane (Z < 0) project as long as theta is within MaxAngle, which is
// what lets it describe lenses wider than 180 degrees.
struct FisheyePolyModel {
  static constexpr CameraModelId kId = CameraModelId::kFisheyePoly;
  static constexpr int kNumParams = 6;
  static constexpr const char* kName = "fisheye-poly";
  static constexpr const char* kParamsInfo = "k1, k2, k3, k4, u0, v0";
  static constexpr bool kNeedsPositiveDepth = false;

  template <typename T>
  static void ProjectPoint(const T* params, const T* point_cam, T* pixel);
  // Newton's method on theta with a bisection safeguard.
  static bool UnprojectPixel(const double* params, const double* pixel, double* bearing);
  static bool UnprojectPixel(const double* params, double max_angle, const double* pixel,
                             double* bearing);
  // Where r(theta) stops increasing, at most pi - kMaxAngleMargin.
  static double MaxAngle(const double* params);
  static bool HasValidParams(const double* params);
};

// Calls `visitor(Model{})` with the model struct of `model_id`, so code generic over models is
// written once: VisitCameraModel(id, [&](auto model) { decltype(model)::ProjectPoint(...); }).
template <typename Visitor>
decltype(auto) VisitCameraModel(CameraModelId model_id, Visitor&& visitor) {
  switch (model_id) {
    case CameraModelId::kPinholeRadtan:
      return visitor(PinholeRadtanModel{});
    case CameraModelId::kKannalaBrandt:
      return visitor(KannalaBrandtModel{});
    case CameraModelId::kFisheyePoly:
      return visitor(FisheyePolyModel{});
  }
  throw std::invalid_argument("invalid CameraModelId " +
                              std::to_string(static_cast<int>(model_id)));
}

// Projects with any model; usable inside Ceres cost functors (T = ceres::Jet).
template <typename T>
void ProjectPoint(CameraModelId model_id, const T* params, const T* point_cam, T* pixel) {
  VisitCameraModel(model_id,
                   [&](auto model) { decltype(model)::ProjectPoint(params, point_cam, pixel); });
}

bool UnprojectPixel(CameraModelId model_id, const double* params, const double* pixel,
                    double* bearing);
// As above with the model's MaxAngle already known (it costs a scan to compute).
bool UnprojectPixel(CameraModelId model_id, const double* params, double max_angle,
                    const double* pixel, double* bearing);
double CameraModelMaxAngle(CameraModelId model_id, const double* params);
bool CameraModelHasValidParams(CameraModelId model_id, const double* params);
bool CameraModelNeedsPositiveDepth(CameraModelId model_id);
int CameraModelNumParams(CameraModelId model_id);
std::string CameraModelParamsInfo(CameraModelId model_id);

std::string CameraModelName(CameraModelId model_id);
// Throws InputError naming the unknown model and listing the valid ones.
CameraModelId CameraModelFromName(const std::string& name);
std::vector<std::string> CameraModelNames();

////////////////////////////////////////////////////////////////////////////////////////////////
// Implementation of the templated projections.
////////////////////////////////////////////////////////////////////////////////////////////////

template <typename T>
void PinholeRadtanModel::ProjectPoint(const T* params, const T* point_cam, T* pixel) {
  const T& fx = params[0];
  const T& fy = params[1];
  const T& cx = params[2];
  const T& cy = params[3];
  const T& k1 = params[4];
  const T& k2 = params[5];
  const T& p1 = params[6];
  const T& p2 = params[7];
  const T& k3 = params[8];

  const T x = point_cam[0] / point_cam[2];
  const T y = point_cam[1] / point_cam[2];
  const T x2 = x * x;
  const T y2 = y * y;
  const T xy = x * y;
  const T r2 = x2 + y2;
  const T radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
  const T x_distorted = x * radial + 2.0 * p1 * xy + p2 * (r2 + 2.0 * x2);
  const T y_distorted = y * radial + p1 * (r2 + 2.0 * y2) + 2.0 * p2 * xy;
  pixel[0] = fx * x_distorted + cx;
  pixel[1] = fy * y_distorted + cy;
}

template <typename T>
void KannalaBrandtModel::ProjectPoint(const T* params, const T* point_cam, T* pixel) {
  using std::atan;
  using std::sqrt;
  const T& fx = params[0];
  const T& fy = params[1];
  const T& cx = params[2];
  const T& cy = params[3];
  const T& k1 = params[4];
  const T& k2 = params[5];
  const T& k3 = params[6];
  const T& k4 = params[7];

  const T a = point_cam[0] / point_cam[2];
  const T b = point_cam[1] / point_cam[2];
  const T r2 = a * a + b * b;
  T scale;  // theta_d / r, the factor that bends the pinhole point.
  if (r2 < kAxisTan2Threshold) {
    // atan(r)/r = 1 - r^2/3 + O(r^4) and theta^2 = r^2 + O(r^4): the limit is 1, as OpenCV's.
    scale = 1.0 + (k1 - 1.0 / 3.0) * r2;
  } else {
    const T r = sqrt(r2);
    const T theta = atan(r);
    const T theta2 = theta * theta;
    const T theta_d = theta * (1.0 + theta2 * (k1 + theta2 * (k2 + theta2 * (k3 + theta2 * k4))));
    scale = theta_d / r;
  }
  pixel[0] = fx * scale * a + cx;
  pixel[1] = fy * scale * b + cy;
}

template <typename T>
void FisheyePolyModel::ProjectPoint(const T* params, const T* point_cam, T* pixel) {
  using std::atan2;
  using std::sqrt;
  const T& k1 = params[0];
  const T& k2 = params[1];
  const T& k3 = params[2];
  const T& k4 = params[3];
  const T& u0 = params[4];
  const T& v0 = params[5];

  const T& x = point_cam[0];
  const T& y = point_cam[1];
  const T& z = point_cam[2];
  const T rho2 = x * x + y * y;
  // r(theta) cos(phi) = (r(theta) / rho) x with rho = sqrt(x^2 + y^2), likewise for sin(phi).
  T scale;
  if (z > 0.0 && rho2 < kAxisTan2Threshold * z * z) {
    // With t = tan(theta) = rho / z, theta = t - t^3/3 + O(t^5), so
    // r(theta) / rho = (k1 + (k2 - k1/3) t^2) / z + O(t^3): the k1 limit of eq. 1 at the axis.
    const T t2 = rho2 / (z * z);
    scale = (k1 + (k2 - k1 / 3.0) * t2) / z;
  } else {
    const T rho = sqrt(rho2);
    const T theta = atan2(rho, z);  // Colatitude, valid for z < 0 too (001 §II).
    const T theta2 = theta * theta;
    const T radius = theta * (k1 + theta2 * (k2 + theta * (k3 + theta * k4)));  // 001 eq. 1
    scale = radius / rho;
  }
  pixel[0] = scale * x + u0;
  pixel[1] = scale * y + v0;
}

}  // namespace pipescope
