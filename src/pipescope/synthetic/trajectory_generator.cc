#include "pipescope/synthetic/trajectory_generator.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "pipescope/util/random.h"

namespace pipescope {
namespace {

constexpr double kDegToRad = M_PI / 180.0;
// Integration steps per frame: fine enough for motion blur sub-samples to interpolate.
constexpr int kStepsPerFrame = 16;
// Stops start and end with a smooth speed ramp of this length.
constexpr double kStopRampS = 0.5;

// Smooth 0..1 window that is 0 during each stop, ramping over kStopRampS at either side.
double StopFactor(double t, const std::vector<double>& stop_starts, double duration) {
  double factor = 1.0;
  for (double start : stop_starts) {
    const double end = start + duration;
    double f = 1.0;
    if (t > start - kStopRampS && t < end + kStopRampS) {
      const double distance = t < start ? start - t : (t > end ? t - end : 0.0);
      const double x = distance / kStopRampS;
      f = x * x * (3.0 - 2.0 * x);
    }
    factor = std::min(factor, f);
  }
  return factor;
}

double WanderWavelength(const MotionOptions& options) {
  return options.wander_wavelength_m > 0.0 ? options.wander_wavelength_m
                                           : options.wobble_wavelength_m;
}

}  // namespace

SmoothNoise::SmoothNoise(std::uint64_t seed, double wavelength) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  double total = 0.0;
  for (int i = 0; i < kTerms; ++i) {
    // Wavelengths spread over about an octave each, amplitudes falling with frequency.
    const double scale = std::pow(0.55, i) * (0.8 + 0.4 * uniform(rng));
    frequency_[i] = 2.0 * M_PI / (wavelength * scale);
    phase_[i] = 2.0 * M_PI * uniform(rng);
    amplitude_[i] = scale;
    total += scale;
  }
  for (double& amplitude : amplitude_) amplitude /= total;
}

double SmoothNoise::operator()(double u) const {
  double value = 0.0;
  for (int i = 0; i < kTerms; ++i) value += amplitude_[i] * std::sin(frequency_[i] * u + phase_[i]);
  return value;
}

TrajectoryGenerator::TrajectoryGenerator(CentrelinePath path, MotionOptions options,
                                         Eigen::Isometry3d body_from_cam)
    : path_(std::move(path)),
      options_(options),
      body_from_cam_(body_from_cam),
      table_dt_(1.0 / (options.fps * kStepsPerFrame)),
      speed_noise_(MixSeed(options.seed, 1), 1.0),  // wavelength in seconds for the speed
      offset_x_(MixSeed(options.seed, 2), WanderWavelength(options)),
      offset_y_(MixSeed(options.seed, 3), WanderWavelength(options)),
      roll_(MixSeed(options.seed, 4), 2.0 * options.wobble_wavelength_m),
      pitch_(MixSeed(options.seed, 5), options.wobble_wavelength_m),
      yaw_(MixSeed(options.seed, 6), options.wobble_wavelength_m),
      heading_(MixSeed(options.seed, 7), 4.0 * options.wobble_wavelength_m) {
  const double duration = options.frames / options.fps;
  // Stops spread evenly over the run, each nudged by up to a quarter of its slot.
  std::vector<double> stop_starts;
  std::mt19937_64 rng(MixSeed(options.seed, 8));
  std::uniform_real_distribution<double> jitter(-0.25, 0.25);
  for (int i = 0; i < options.stop_count; ++i) {
    const double slot = duration / (options.stop_count + 1);
    stop_starts.push_back(slot * (i + 1 + jitter(rng)));
  }
  const double turnaround = options.start_s_m + options.travel_m;
  double s = options.start_s_m;
  double driven = 0.0;
  int direction = 1;
  const int steps = static_cast<int>(std::ceil(duration / table_dt_)) + kStepsPerFrame + 1;
  arc_length_.reserve(steps);
  driven_.reserve(steps);
  for (int k = 0; k < steps; ++k) {
    arc_length_.push_back(s);
    driven_.push_back(driven);
    const double t = k * table_dt_;
    const double speed = options.speed_m_s *
                         (1.0 + options.speed_variation * speed_noise_(t / 4.0)) *
                         StopFactor(t, stop_starts, options.stop_duration_s);
    double step = direction * speed * table_dt_;
    if (direction > 0 && s + step >= turnaround) {
      step = turnaround - s;
      direction = options.out_and_back ? -1 : 0;
    } else if (direction < 0 && s + step <= options.start_s_m) {
      step = options.start_s_m - s;
      direction = 0;
    }
    s += step;
    driven += std::abs(step);
  }
}

void TrajectoryGenerator::Sample(double t, double* s, double* driven) const {
  const double position = std::clamp(t / table_dt_, 0.0, arc_length_.size() - 1.0);
  const std::size_t k = std::min(static_cast<std::size_t>(position), arc_length_.size() - 2);
  const double w = position - k;
  *s = (1.0 - w) * arc_length_[k] + w * arc_length_[k + 1];
  *driven = (1.0 - w) * driven_[k] + w * driven_[k + 1];
}

double TrajectoryGenerator::ArcLength(double t) const {
  double s, driven;
  Sample(t, &s, &driven);
  return s;
}

Eigen::Isometry3d TrajectoryGenerator::BodyFrame(double s) const {
  Eigen::Vector3d point, tangent;
  path_.Evaluate(s, &point, &tangent);
  // y towards world down (+Y) as far as the tangent allows; x completes a right-handed frame.
  Eigen::Vector3d down = Eigen::Vector3d::UnitY() - Eigen::Vector3d::UnitY().dot(tangent) * tangent;
  if (down.norm() < 1e-6) down = Eigen::Vector3d::UnitX() - tangent.x() * tangent;
  down.normalize();
  Eigen::Matrix3d rotation;
  rotation.col(0) = down.cross(tangent);
  rotation.col(1) = down;
  rotation.col(2) = tangent;
  Eigen::Isometry3d world_from_body = Eigen::Isometry3d::Identity();
  world_from_body.linear() = rotation;
  world_from_body.translation() = point;
  return world_from_body;
}

Eigen::Isometry3d TrajectoryGenerator::NominalWorldFromCam(double s) const {
  return BodyFrame(s) * body_from_cam_;
}

Eigen::Isometry3d TrajectoryGenerator::WorldFromCam(double t) const {
  double s, u;
  Sample(t, &s, &u);
  Eigen::Isometry3d world_from_body = BodyFrame(s);
  // Offsets and angles are functions of the distance driven u, so a stopped robot is still.
  world_from_body.translate(Eigen::Vector3d(options_.lateral_offset_m * offset_x_(u),
                                            options_.lateral_offset_m * offset_y_(u), 0.0));
  const double roll = options_.roll_deg * kDegToRad * roll_(u);
  const double pitch = options_.wobble_deg * kDegToRad * pitch_(u);
  const double yaw =
      options_.wobble_deg * kDegToRad * yaw_(u) + options_.heading_deg * kDegToRad * heading_(u);
  world_from_body.rotate(Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ()) *
                         Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()) *
                         Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitX()));
  return world_from_body * body_from_cam_;
}

Trajectory TrajectoryGenerator::Frames() const {
  Trajectory trajectory;
  trajectory.reserve(options_.frames);
  for (int i = 0; i < options_.frames; ++i) {
    const double t = i / options_.fps;
    const Eigen::Isometry3d pose = WorldFromCam(t);
    StampedPose stamped;
    stamped.timestamp = t;
    stamped.rotation = Eigen::Quaterniond(pose.linear()).normalized();
    stamped.position = pose.translation();
    trajectory.push_back(stamped);
  }
  return trajectory;
}

}  // namespace pipescope
