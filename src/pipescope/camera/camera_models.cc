#include "pipescope/camera/camera_models.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "pipescope/util/error.h"

namespace pipescope {
namespace {

constexpr double kPi = std::numbers::pi;

// Steps of the scan for the first non-increasing angle. The radial derivatives are polynomials
// of degree <= 8 in the angle, so a dip narrower than cap/4096 (< 0.05 degrees) is not a
// realistic calibration.
constexpr int kNumScanSteps = 4096;
constexpr int kMaxIterations = 100;

// Returns the largest angle in [0, cap] up to which `derivative` (of a radial mapping with
// respect to the angle) stays positive: a scan finds the first non-positive sample, bisection
// refines the sign change. Returns 0 when the mapping does not even start increasing.
template <typename Derivative>
double LastIncreasingAngle(const Derivative& derivative, double cap) {
  if (!(derivative(0.0) > 0.0)) return 0.0;
  double previous = 0.0;
  for (int i = 1; i <= kNumScanSteps; ++i) {
    const double angle = cap * i / kNumScanSteps;
    if (!(derivative(angle) > 0.0)) {
      double lo = previous;
      double hi = angle;
      for (int k = 0; k < 200 && hi - lo > 1e-15; ++k) {
        const double mid = 0.5 * (lo + hi);
        (derivative(mid) > 0.0 ? lo : hi) = mid;
      }
      return lo;
    }
    previous = angle;
  }
  return cap;
}

// Solves mapping(angle) = target for angle in [0, max_angle], where mapping(0) = 0 and the
// mapping increases on the interval: Newton's method inside a shrinking bracket, falling back to
// bisection whenever a Newton step would leave the bracket. `mapping(angle, &value,
// &derivative)`. Returns false when the target lies beyond mapping(max_angle).
template <typename Mapping>
bool InvertIncreasingMapping(const Mapping& mapping, double target, double max_angle,
                             double* angle) {
  if (target <= 0.0) {
    *angle = 0.0;
    return true;
  }
  double value = 0.0;
  double slope = 0.0;
  mapping(max_angle, &value, &slope);
  if (target >= value) {
    // Allow rounding slack so that a point projected exactly at the limit comes back.
    if (target - value > 1e-12 * std::max(1.0, value)) return false;
    *angle = max_angle;
    return true;
  }
  mapping(0.0, &value, &slope);
  double lo = 0.0;
  double hi = max_angle;
  double x = slope > 0.0 ? std::clamp(target / slope, lo, hi) : 0.5 * hi;
  for (int i = 0; i < kMaxIterations; ++i) {
    mapping(x, &value, &slope);
    const double residual = value - target;
    if (residual == 0.0) break;
    (residual < 0.0 ? lo : hi) = x;
    double next = x - residual / slope;
    if (!(slope > 0.0) || !(next > lo && next < hi)) next = 0.5 * (lo + hi);
    const bool converged = std::abs(next - x) <= 1e-15 * std::max(1.0, x);
    x = next;
    if (converged || hi - lo <= 1e-15 * std::max(1.0, hi)) break;
  }
  *angle = x;
  return true;
}

bool AllFinite(const double* values, int count) {
  return std::all_of(values, values + count, [](double v) { return std::isfinite(v); });
}

// The radtan distortion of the normalised point (x, y) and its 2x2 Jacobian.
void DistortRadtan(const double* params, double x, double y, double* distorted, double* jacobian) {
  const double k1 = params[4], k2 = params[5], p1 = params[6], p2 = params[7], k3 = params[8];
  const double x2 = x * x, y2 = y * y, xy = x * y, r2 = x2 + y2;
  const double radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
  const double d_radial_d_r2 = k1 + r2 * (2.0 * k2 + 3.0 * r2 * k3);
  distorted[0] = x * radial + 2.0 * p1 * xy + p2 * (r2 + 2.0 * x2);
  distorted[1] = y * radial + p1 * (r2 + 2.0 * y2) + 2.0 * p2 * xy;
  // Row-major [d(xd)/dx, d(xd)/dy; d(yd)/dx, d(yd)/dy]; d(r2)/dx = 2x.
  const double cross = 2.0 * xy * d_radial_d_r2 + 2.0 * p1 * x + 2.0 * p2 * y;
  jacobian[0] = radial + 2.0 * x2 * d_radial_d_r2 + 2.0 * p1 * y + 6.0 * p2 * x;
  jacobian[1] = cross;
  jacobian[2] = cross;
  jacobian[3] = radial + 2.0 * y2 * d_radial_d_r2 + 6.0 * p1 * y + 2.0 * p2 * x;
}

}  // namespace

////////////////////////////////////////////////////////////////////////////////////////////////
// PinholeRadtanModel
////////////////////////////////////////////////////////////////////////////////////////////////

double PinholeRadtanModel::MaxAngle(const double* params) {
  const double k1 = params[4], k2 = params[5], k3 = params[8];
  // d/dr [r (1 + k1 r^2 + k2 r^4 + k3 r^6)] has the sign of the derivative in the angle
  // because r = tan(angle) increases. The tangential terms are left out: they are small and
  // have no radial fold of their own.
  return LastIncreasingAngle(
      [&](double angle) {
        const double r = std::tan(angle);
        const double r2 = r * r;
        return 1.0 + r2 * (3.0 * k1 + r2 * (5.0 * k2 + r2 * 7.0 * k3));
      },
      kPi / 2.0 - kMaxAngleMargin);
}

bool PinholeRadtanModel::UnprojectPixel(const double* params, const double* pixel,
                                        double* bearing) {
  return UnprojectPixel(params, MaxAngle(params), pixel, bearing);
}

bool PinholeRadtanModel::UnprojectPixel(const double* params, double max_angle, const double* pixel,
                                        double* bearing) {
  const double target[2] = {(pixel[0] - params[2]) / params[0], (pixel[1] - params[3]) / params[1]};
  // Keep iterates inside the valid disc so Newton cannot wander onto the far side of a fold.
  const double max_radius = std::tan(max_angle);
  const auto clamp_to_disc = [max_radius](double* point) {
    const double radius = std::hypot(point[0], point[1]);
    if (radius > max_radius) {
      point[0] *= max_radius / radius;
      point[1] *= max_radius / radius;
    }
  };
  double point[2] = {target[0], target[1]};
  clamp_to_disc(point);
  double distorted[2];
  double jacobian[4];
  DistortRadtan(params, point[0], point[1], distorted, jacobian);
  double error = std::hypot(distorted[0] - target[0], distorted[1] - target[1]);
  const double tolerance = 1e-15 * std::max(1.0, std::hypot(target[0], target[1]));
  for (int i = 0; i < kMaxIterations && error > tolerance; ++i) {
    // Newton step J delta = residual, solved in closed form for the 2x2 system.
    const double det = jacobian[0] * jacobian[3] - jacobian[1] * jacobian[2];
    if (!(std::abs(det) > 0.0)) break;
    const double rx = distorted[0] - target[0];
    const double ry = distorted[1] - target[1];
    const double delta[2] = {(jacobian[3] * rx - jacobian[1] * ry) / det,
                             (jacobian[0] * ry - jacobian[2] * rx) / det};
    // Backtracking: halve the step until the residual decreases.
    bool improved = false;
    for (double step = 1.0; step > 1e-6; step *= 0.5) {
      double candidate[2] = {point[0] - step * delta[0], point[1] - step * delta[1]};
      clamp_to_disc(candidate);
      double candidate_distorted[2];
      double candidate_jacobian[4];
      DistortRadtan(params, candidate[0], candidate[1], candidate_distorted, candidate_jacobian);
      const double candidate_error =
          std::hypot(candidate_distorted[0] - target[0], candidate_distorted[1] - target[1]);
      if (candidate_error < error) {
        std::copy(candidate, candidate + 2, point);
        std::copy(candidate_distorted, candidate_distorted + 2, distorted);
        std::copy(candidate_jacobian, candidate_jacobian + 4, jacobian);
        error = candidate_error;
        improved = true;
        break;
      }
    }
    if (!improved) break;
  }
  // A residual left over means the pixel has no pre-image inside the valid disc.
  if (!(error <= 1e-9 * std::max(1.0, std::hypot(target[0], target[1])))) return false;
  if (std::atan(std::hypot(point[0], point[1])) > max_angle) return false;
  const double norm = std::sqrt(point[0] * point[0] + point[1] * point[1] + 1.0);
  bearing[0] = point[0] / norm;
  bearing[1] = point[1] / norm;
  bearing[2] = 1.0 / norm;
  return true;
}

bool PinholeRadtanModel::HasValidParams(const double* params) {
  return AllFinite(params, kNumParams) && params[0] > 0.0 && params[1] > 0.0;
}

////////////////////////////////////////////////////////////////////////////////////////////////
// KannalaBrandtModel
////////////////////////////////////////////////////////////////////////////////////////////////

double KannalaBrandtModel::MaxAngle(const double* params) {
  const double k1 = params[4], k2 = params[5], k3 = params[6], k4 = params[7];
  return LastIncreasingAngle(
      [&](double theta) {
        const double t2 = theta * theta;
        return 1.0 + t2 * (3.0 * k1 + t2 * (5.0 * k2 + t2 * (7.0 * k3 + t2 * 9.0 * k4)));
      },
      kPi / 2.0 - kMaxAngleMargin);
}

bool KannalaBrandtModel::UnprojectPixel(const double* params, const double* pixel,
                                        double* bearing) {
  return UnprojectPixel(params, MaxAngle(params), pixel, bearing);
}

bool KannalaBrandtModel::UnprojectPixel(const double* params, double max_angle, const double* pixel,
                                        double* bearing) {
  const double k1 = params[4], k2 = params[5], k3 = params[6], k4 = params[7];
  const double mx = (pixel[0] - params[2]) / params[0];
  const double my = (pixel[1] - params[3]) / params[1];
  const double theta_d = std::hypot(mx, my);
  double theta = 0.0;
  const bool inside = InvertIncreasingMapping(
      [&](double t, double* value, double* slope) {
        const double t2 = t * t;
        *value = t * (1.0 + t2 * (k1 + t2 * (k2 + t2 * (k3 + t2 * k4))));
        *slope = 1.0 + t2 * (3.0 * k1 + t2 * (5.0 * k2 + t2 * (7.0 * k3 + t2 * 9.0 * k4)));
      },
      theta_d, max_angle, &theta);
  if (!inside) return false;
  // The bearing keeps the azimuth of (mx, my); sin(theta)/theta_d -> 1 at the axis.
  const double scale = theta_d > 0.0 ? std::sin(theta) / theta_d : 1.0;
  bearing[0] = scale * mx;
  bearing[1] = scale * my;
  bearing[2] = std::cos(theta);
  return true;
}

bool KannalaBrandtModel::HasValidParams(const double* params) {
  return AllFinite(params, kNumParams) && params[0] > 0.0 && params[1] > 0.0;
}

////////////////////////////////////////////////////////////////////////////////////////////////
// FisheyePolyModel
////////////////////////////////////////////////////////////////////////////////////////////////

double FisheyePolyModel::MaxAngle(const double* params) {
  const double k1 = params[0], k2 = params[1], k3 = params[2], k4 = params[3];
  // dr/dtheta of 001 eq. 1.
  return LastIncreasingAngle(
      [&](double theta) {
        return k1 + theta * theta * (3.0 * k2 + theta * (4.0 * k3 + theta * 5.0 * k4));
      },
      kPi - kMaxAngleMargin);
}

bool FisheyePolyModel::UnprojectPixel(const double* params, const double* pixel, double* bearing) {
  return UnprojectPixel(params, MaxAngle(params), pixel, bearing);
}

bool FisheyePolyModel::UnprojectPixel(const double* params, double max_angle, const double* pixel,
                                      double* bearing) {
  const double k1 = params[0], k2 = params[1], k3 = params[2], k4 = params[3];
  const double du = pixel[0] - params[4];
  const double dv = pixel[1] - params[5];
  const double radius = std::hypot(du, dv);
  double theta = 0.0;
  const bool inside = InvertIncreasingMapping(
      [&](double t, double* value, double* slope) {
        const double t2 = t * t;
        *value = t * (k1 + t2 * (k2 + t * (k3 + t * k4)));
        *slope = k1 + t2 * (3.0 * k2 + t * (4.0 * k3 + t * 5.0 * k4));
      },
      radius, max_angle, &theta);
  if (!inside) return false;
  // Eq. 1 read backwards: the point on the view sphere at colatitude theta, longitude phi.
  const double sin_theta = std::sin(theta);
  bearing[0] = radius > 0.0 ? sin_theta * du / radius : 0.0;
  bearing[1] = radius > 0.0 ? sin_theta * dv / radius : 0.0;
  bearing[2] = std::cos(theta);
  return true;
}

bool FisheyePolyModel::HasValidParams(const double* params) {
  return AllFinite(params, kNumParams) && params[0] > 0.0;
}

////////////////////////////////////////////////////////////////////////////////////////////////
// Dispatch by id
////////////////////////////////////////////////////////////////////////////////////////////////

bool UnprojectPixel(CameraModelId model_id, const double* params, const double* pixel,
                    double* bearing) {
  return VisitCameraModel(model_id, [&](auto model) {
    return decltype(model)::UnprojectPixel(params, pixel, bearing);
  });
}

bool UnprojectPixel(CameraModelId model_id, const double* params, double max_angle,
                    const double* pixel, double* bearing) {
  return VisitCameraModel(model_id, [&](auto model) {
    return decltype(model)::UnprojectPixel(params, max_angle, pixel, bearing);
  });
}

double CameraModelMaxAngle(CameraModelId model_id, const double* params) {
  return VisitCameraModel(model_id, [&](auto model) { return decltype(model)::MaxAngle(params); });
}

bool CameraModelHasValidParams(CameraModelId model_id, const double* params) {
  return VisitCameraModel(model_id,
                          [&](auto model) { return decltype(model)::HasValidParams(params); });
}

bool CameraModelNeedsPositiveDepth(CameraModelId model_id) {
  return VisitCameraModel(model_id,
                          [](auto model) { return decltype(model)::kNeedsPositiveDepth; });
}

int CameraModelNumParams(CameraModelId model_id) {
  return VisitCameraModel(model_id, [](auto model) { return decltype(model)::kNumParams; });
}

std::string CameraModelParamsInfo(CameraModelId model_id) {
  return VisitCameraModel(model_id,
                          [](auto model) { return std::string(decltype(model)::kParamsInfo); });
}

std::string CameraModelName(CameraModelId model_id) {
  return VisitCameraModel(model_id, [](auto model) { return std::string(decltype(model)::kName); });
}

std::vector<std::string> CameraModelNames() {
  return {PinholeRadtanModel::kName, KannalaBrandtModel::kName, FisheyePolyModel::kName};
}

CameraModelId CameraModelFromName(const std::string& name) {
  for (const CameraModelId id : {CameraModelId::kPinholeRadtan, CameraModelId::kKannalaBrandt,
                                 CameraModelId::kFisheyePoly}) {
    if (name == CameraModelName(id)) return id;
  }
  std::string valid;
  for (const std::string& model_name : CameraModelNames()) {
    valid += (valid.empty() ? "" : ", ") + model_name;
  }
  throw InputError("unknown camera model '" + name + "' (valid models: " + valid + ")");
}

}  // namespace pipescope
