#pragma once

#include "pipescope/synthetic/centreline_path.h"
#include "pipescope/synthetic/scene.h"
#include "pipescope/synthetic/simulation_config.h"

namespace pipescope {

// A pipe layout and the robot's route through it.
struct Layout {
  Scene scene;
  CentrelinePath route;
  double start_s_m = 0.0;  // where the run starts on the route
  double travel_m = 0.0;   // how far the robot may drive before it turns back or stops
};

// Builds the layout named by config.layout:
// - straight: one pipe along +Z from the origin, length_m long (000, 003);
// - bend-tube: straight, bend, straight in the X-Z plane (004);
// - square-loop: four T-intersections T1..T4 whose centre distances follow 001 Table I, each
//   side's pipe running on past the next T as that T's dead-end arm; the route starts in T1's
//   arm and turns at T1, T2, T3 and T4, ending 1 m before T1 (001 dataset A).
Layout BuildLayout(const SimulationConfig& config);

// The T centres of the square loop in the X-Z plane: the least-squares fit to the six centre
// distances of 001 Table I, T1 at the origin, T2 on +Z, T3 to the left of T1 -> T2 (right when
// mirrored).
std::vector<Eigen::Vector3d> SquareLoopCorners(bool mirror);

}  // namespace pipescope
