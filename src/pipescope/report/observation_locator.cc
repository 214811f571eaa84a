#include "pipescope/report/observation_locator.h"

#include <algorithm>
#include <cmath>

#include "pipescope/util/error.h"

namespace pipescope {
namespace {

// Border samples of a box: its corners and every this many pixels along its edges.
constexpr double kBorderStepPx = 8.0;

std::vector<Eigen::Vector2d> BoxBorder(const Observation& o) {
  std::vector<Eigen::Vector2d> pixels;
  const int nu = std::max(1, static_cast<int>(std::ceil((o.u_max - o.u_min) / kBorderStepPx)));
  const int nv = std::max(1, static_cast<int>(std::ceil((o.v_max - o.v_min) / kBorderStepPx)));
  for (int i = 0; i <= nu; ++i) {
    const double u = o.u_min + (o.u_max - o.u_min) * i / nu;
    pixels.emplace_back(u, o.v_min);
    pixels.emplace_back(u, o.v_max);
  }
  for (int j = 1; j < nv; ++j) {
    const double v = o.v_min + (o.v_max - o.v_min) * j / nv;
    pixels.emplace_back(o.u_min, v);
    pixels.emplace_back(o.u_max, v);
  }
  return pixels;
}

}  // namespace

LocatedObservation LocateObservation(const RunFiles& run, const Camera& camera,
                                     const Observation& observation) {
  if (run.station_options.line != SurveyLine::kStraightAxis) {
    // Fitted to a map's own points (0.3 m either side of the camera), the pipe's cylinder was
    // good to 2-3 mm, but the map's camera orientations drift (12 degrees over 0.6 m on the
    // simulated fisheye run): rays from them would miss the true wall point by centimetres.
    throw InputError(run.dir.string() +
                     ": locating wall points is implemented for odometry runs of a straight pipe; "
                     "a map run's camera orientations are not accurate enough yet to place them");
  }
  if (!(run.radius_m > 0.0)) {
    throw InputError(run.dir.string() +
                     ": the run's dataset gave no pipe radius, so no pixel can "
                     "be placed on the wall");
  }
  LocatedObservation located;
  located.observation = observation;
  const Station* station = run.StationOfFrame(observation.frame);
  if (station == nullptr) {
    located.why_not = "frame " + std::to_string(observation.frame) + " has no pose in the run";
    return located;
  }
  const std::size_t index = station - run.stations.data();
  const Eigen::Isometry3d world_from_cam = ToIsometry(run.trajectory[index]);
  const auto locate = [&](const Eigen::Vector2d& pixel) {
    // An odometry run's pipe: its axis is the run frame's Z axis (GUIDE §3).
    return LocateOnCylinder(camera, world_from_cam, *station, pixel, run.radius_m, PipeAxis{},
                            run.station_options.up);
  };
  const std::optional<WallLocation> centre = locate({observation.u(), observation.v()});
  if (!centre) {
    located.why_not =
        "the pixel's ray does not meet the wall (outside the lens's view, or along "
        "the pipe)";
    return located;
  }
  located.located = true;
  located.centre = *centre;
  located.distance_from_m = located.distance_to_m = centre->distance_m;
  std::vector<double> clocks = {centre->clock_angle_deg};
  if (observation.box) {
    for (const Eigen::Vector2d& pixel : BoxBorder(observation)) {
      const std::optional<WallLocation> border = locate(pixel);
      if (!border) continue;
      located.distance_from_m = std::min(located.distance_from_m, border->distance_m);
      located.distance_to_m = std::max(located.distance_to_m, border->distance_m);
      clocks.push_back(border->clock_angle_deg);
    }
  }
  const auto [from, to] = ClockSpan(clocks);
  located.clock_from_deg = from;
  located.clock_to_deg = to;
  return located;
}

}  // namespace pipescope
