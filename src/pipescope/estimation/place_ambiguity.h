#pragma once

#include <vector>

namespace pipescope {

// One place along a later pass that a loop candidate's earlier key frame was matched to (its
// path along that pass, and the PnP inliers of the edge it gave).
struct PlaceMatch {
  double path_m = 0.0;
  int inliers = 0;
};

// Whether a candidate's best place stands out. On a wall that repeats along the pipe (painted
// rings, joints), a candidate whose runner-up matches about as well as its best place cannot tell
// which is the right one.
struct PlaceJudgement {
  // The strongest of the places at least `separation_m` along the pass from the best one: another
  // place, not the best one's neighbour, which sees much the same wall. -1 when there is none.
  int runner_up = -1;
  // The runner-up has `max_runner_up_share` of the best place's inliers or more.
  bool ambiguous = false;
};

PlaceJudgement JudgeBestPlace(const std::vector<PlaceMatch>& places, int best, double separation_m,
                              double max_runner_up_share);

}  // namespace pipescope
