#include "pipescope/synthetic/scene_layouts.h"

#include <ceres/ceres.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <stdexcept>

namespace pipescope {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

// 001 Table I, laser distances between T centres (m).
constexpr double kT1T2 = 8.150, kT2T3 = 8.174, kT3T4 = 8.159, kT4T1 = 8.110, kT1T3 = 11.468,
                 kT2T4 = 11.493;

// Residual of one measured distance between two T centres in the X-Z plane.
struct TeeDistanceResidual {
  double measured;
  template <typename T>
  bool operator()(const T* a, const T* b, T* residual) const {
    using std::sqrt;
    const T dx = a[0] - b[0];
    const T dz = a[1] - b[1];
    residual[0] = sqrt(dx * dx + dz * dz) - measured;
    return true;
  }
};

// The route ends this far before T1, a near-full loop as in dataset A.
constexpr double kLoopEndBeforeT1M = 1.0;

// Of the two intersections of circles about a (radius ra) and b (radius rb) in the X-Z plane,
// the one on the left of a->b (positive cross product about +Y) unless `right`.
Eigen::Vector3d CircleIntersection(const Eigen::Vector3d& a, double ra, const Eigen::Vector3d& b,
                                   double rb, bool right) {
  const double d = (b - a).norm();
  const double along = (ra * ra - rb * rb + d * d) / (2.0 * d);
  const double across = std::sqrt(std::max(0.0, ra * ra - along * along));
  const Eigen::Vector3d u = (b - a) / d;
  Eigen::Vector3d v = Eigen::Vector3d::UnitY().cross(u);
  if (right) v = -v;
  return a + along * u + across * v;
}

Layout StraightLayout(const SimulationConfig& c) {
  Scene scene;
  const Eigen::Vector3d start = Eigen::Vector3d::Zero();
  const Eigen::Vector3d end(0.0, 0.0, c.length_m);
  scene.AddStraight(start, end, c.radius_m);
  return {std::move(scene), CentrelinePath({start, end}, 1.0), c.end_margin_m,
          c.length_m - 2.0 * c.end_margin_m};
}

Layout BendTubeLayout(const SimulationConfig& c) {
  const double angle = c.bend_angle_deg * kDegToRad;
  const Eigen::Vector3d in = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d turn = Eigen::Vector3d::UnitX();
  const Eigen::Vector3d out = std::cos(angle) * in + std::sin(angle) * turn;
  Scene scene;
  const Eigen::Vector3d bend_start(0.0, 0.0, c.length_m);
  scene.AddStraight(Eigen::Vector3d::Zero(), bend_start, c.radius_m);
  const int bend = scene.AddBend(bend_start, in, turn, c.bend_radius_m, angle, c.radius_m);
  const Eigen::Vector3d bend_end = scene.sections()[bend].EndPoint();
  const Eigen::Vector3d tube_end = bend_end + c.length_m * out;
  scene.AddStraight(bend_end, tube_end, c.radius_m);
  // The route's rounded corner is the bend's centreline: its tangent points lie R tan(A/2)
  // from the corner.
  const Eigen::Vector3d corner = bend_start + c.bend_radius_m * std::tan(angle / 2.0) * in;
  CentrelinePath route({Eigen::Vector3d::Zero(), corner, tube_end}, c.bend_radius_m);
  const double travel = route.Length() - 2.0 * c.end_margin_m;
  return {std::move(scene), std::move(route), c.end_margin_m, travel};
}

Layout SquareLoopLayout(const SimulationConfig& c) {
  // length_m sets the size of the loop: the T1-T2 distance, the others scaled alike.
  std::vector<Eigen::Vector3d> t = SquareLoopCorners(c.mirror_loop);
  for (Eigen::Vector3d& corner : t) corner *= c.length_m / kT1T2;
  Scene scene;
  // Side i runs from T_i (where it leaves as a branch) through T_{i+1} (as that T's through
  // run) on to T_{i+1}'s dead-end arm. Side 4 (T4 -> T1 and T1's arm) holds the start.
  const int order[] = {3, 0, 1, 2};
  for (int k = 0; k < 4; ++k) {
    const int i = order[k];
    const Eigen::Vector3d& from = t[i];
    const Eigen::Vector3d& to = t[(i + 1) % 4];
    const Eigen::Vector3d direction = (to - from).normalized();
    scene.AddStraight(from, to + c.stub_m * direction, c.radius_m);
    const int next = (i + 1) % 4;
    scene.AddTee("T" + std::to_string(next + 1), t[next]);
  }
  // Both routes start in T1's dead-end arm.
  const Eigen::Vector3d d41 = (t[0] - t[3]).normalized();
  const Eigen::Vector3d start = t[0] + (c.stub_m - c.end_margin_m) * d41;
  std::vector<Eigen::Vector3d> waypoints = {start, t[0], t[1],
                                            t[2],  t[3], t[0] - kLoopEndBeforeT1M * d41};
  if (c.route == "B") {
    // Straight through T1 to T4, round the loop the other way back to T1, along T1-T4 a second
    // time, and at T4 into its dead-end arm (side 3's run beyond T4).
    const Eigen::Vector3d d34 = (t[3] - t[2]).normalized();
    waypoints = {start, t[3], t[2], t[1], t[0], t[3], t[3] + (c.stub_m - c.end_margin_m) * d34};
  }
  CentrelinePath route(waypoints, c.turn_radius_m);
  const double travel = route.Length();
  return {std::move(scene), std::move(route), 0.0, travel};
}

}  // namespace

std::vector<Eigen::Vector3d> SquareLoopCorners(bool mirror) {
  // Start from the quadrilateral through five of the distances, then fit all six (the laser
  // figures are not exactly consistent) by least squares, with T1 at the origin and T2 on +Z.
  const Eigen::Vector3d t1 = Eigen::Vector3d::Zero();
  const Eigen::Vector3d t2(0.0, 0.0, kT1T2);
  const Eigen::Vector3d t3 = CircleIntersection(t1, kT1T3, t2, kT2T3, mirror);
  const Eigen::Vector3d t4 = CircleIntersection(t1, kT4T1, t3, kT3T4, mirror);
  std::array<std::array<double, 2>, 4> xz;
  for (const auto& [index, corner] : {std::pair{0, t1}, {1, t2}, {2, t3}, {3, t4}}) {
    xz[index] = {corner.x(), corner.z()};
  }
  ceres::Problem problem;
  const std::tuple<int, int, double> measured[] = {{0, 1, kT1T2}, {1, 2, kT2T3}, {2, 3, kT3T4},
                                                   {3, 0, kT4T1}, {0, 2, kT1T3}, {1, 3, kT2T4}};
  for (const auto& [a, b, distance] : measured) {
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<TeeDistanceResidual, 1, 2, 2>(
                                 new TeeDistanceResidual{distance}),
                             nullptr, xz[a].data(), xz[b].data());
  }
  problem.SetParameterBlockConstant(xz[0].data());
  problem.SetManifold(xz[1].data(), new ceres::SubsetManifold(2, {0}));  // T2 stays on +Z
  ceres::Solver::Options options;
  options.function_tolerance = 1e-14;
  options.parameter_tolerance = 1e-14;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  if (!summary.IsSolutionUsable()) {
    throw std::runtime_error("square-loop fit failed: " + summary.BriefReport());
  }
  std::vector<Eigen::Vector3d> corners;
  for (const auto& point : xz) corners.emplace_back(point[0], 0.0, point[1]);
  return corners;
}

Layout BuildLayout(const SimulationConfig& config) {
  if (config.layout == "bend-tube") return BendTubeLayout(config);
  if (config.layout == "square-loop") return SquareLoopLayout(config);
  return StraightLayout(config);
}

}  // namespace pipescope
