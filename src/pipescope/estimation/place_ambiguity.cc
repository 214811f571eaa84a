#include "pipescope/estimation/place_ambiguity.h"

#include <cmath>
#include <stdexcept>

namespace pipescope {

PlaceJudgement JudgeBestPlace(const std::vector<PlaceMatch>& places, int best, double separation_m,
                              double max_runner_up_share) {
  if (best < 0 || best >= static_cast<int>(places.size())) {
    throw std::invalid_argument("JudgeBestPlace: best is not one of the places");
  }
  PlaceJudgement judgement;
  for (int i = 0; i < static_cast<int>(places.size()); ++i) {
    if (std::abs(places[i].path_m - places[best].path_m) < separation_m) continue;
    if (judgement.runner_up < 0 || places[i].inliers > places[judgement.runner_up].inliers) {
      judgement.runner_up = i;
    }
  }
  judgement.ambiguous = judgement.runner_up >= 0 && places[judgement.runner_up].inliers >=
                                                        max_runner_up_share * places[best].inliers;
  return judgement;
}

}  // namespace pipescope
