#include "pipescope/estimation/place_ambiguity.h"

#include <cmath>
#include <stdexcept>

namespace pipescope {

int RunnerUpPlace(const std::vector<PlaceMatch>& places, int best, double separation_m) {
  if (best < 0 || best >= static_cast<int>(places.size())) {
    throw std::invalid_argument("RunnerUpPlace: best is not one of the places");
  }
  int runner_up = -1;
  for (int i = 0; i < static_cast<int>(places.size()); ++i) {
    if (std::abs(places[i].path_m - places[best].path_m) < separation_m) continue;
    if (runner_up < 0 || places[i].inliers > places[runner_up].inliers) runner_up = i;
  }
  return runner_up;
}

}  // namespace pipescope
