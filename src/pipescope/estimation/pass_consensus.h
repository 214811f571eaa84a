#pragma once

#include <vector>

namespace pipescope {

// Which loop edges between two passes of one section agree with each other (001 §III-E checks
// none; here a wall pattern that repeats along the pipe, such as painted rings or joints every
// metre, gave PnP-confirmed edges between places metres apart). Each edge pairs a place on the
// earlier pass, `earlier_path_m` along it, with one on the later pass, `later_path_m` along
// that pass's own odometry. The later pass may have lost its scale, so the places of correct
// edges lie on a line earlier = a + b * later with b > 0; the largest set of edges within
// `tolerance_m` of one such line (RANSAC over every two edges; b bounded) is kept. Returns their
// indices, ascending; fewer than two edges, or none agreeing, give the single edge with index 0 or
// none.
struct PassConsensusOptions {
  double tolerance_m = 0.3;
  // b within [1 / max_scale_ratio, max_scale_ratio]: a line nearly flat would hold every edge
  // whose earlier place is about the same, wherever its later place.
  double max_scale_ratio = 5.0;
  double min_later_separation_m = 0.01;  // two edges closer on the later pass fix no slope
};

std::vector<int> ConsistentLoopEdges(const std::vector<double>& earlier_path_m,
                                     const std::vector<double>& later_path_m,
                                     const PassConsensusOptions& options = {});

}  // namespace pipescope
