#pragma once

#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "pipescope/eval/alignment.h"

namespace pipescope {

// Distance between two junctions in ground truth and in the estimate (001 Table I).
struct JunctionDistance {
  std::string from;  // Scene junction names.
  std::string to;
  double gt_m = 0;
  double est_m = 0;
  double error_m = 0;    // est_m - gt_m, signed.
  double error_pct = 0;  // 100 |error_m| / gt_m.
};

// How well a dense appearance map's grey values follow the simulated wall's albedo, after a
// high-pass, at the whole-cell shift that correlates best (eval/dense_map_agreement.h).
struct DenseMapAgreement {
  double correlation = std::numeric_limits<double>::quiet_NaN();
  int cells = 0;  // map cells compared at the best shift
  int shift_rows = 0;  // along the axis
  int shift_cols = 0;  // around it
  // The best shift lies on the search's edge: the map may be misplaced by more than the search
  // covers, and the correlation then says little about its appearance.
  bool shift_at_limit = false;
};

// One piece of a `map` run's dense appearance map against the simulated albedo.
struct DensePieceAgreement {
  int piece = 0;  // index in run.json dense_map.pieces
  int section = 0;
  std::string part;  // straight, t-red or t-blue
  int keyframes_used = 0;
  DenseMapAgreement agreement;
};

// Everything metrics.json holds (GUIDE §4). Optional fields are null in JSON when unset.
struct Metrics {
  std::size_t frames_gt = 0;
  std::size_t frames_est = 0;
  std::size_t frames_matched = 0;

  // Whether the ground truth goes out and comes back; not a metrics.json key, but it decides
  // which distances are reported.
  bool out_and_back = false;
  // Net distance travelled (one-way) or forward + reverse legs (out-and-back), metres.
  double distance_gt_m = 0;
  double distance_est_m = 0;
  std::optional<double> distance_error_pct;  // 000 eq. 50; unset when distance_gt_m is 0.
  // Out-and-back runs only.
  std::optional<double> forward_error_pct;
  std::optional<double> reverse_error_pct;
  std::optional<double> return_error_pct;  // 000 eq. 51.
  // Length of the path travelled (every run): what distances along the pipe measure through a
  // network's turns, where the net distance above is the chord from start to end, which the
  // turns' angles move. Unset when path_gt_m is 0.
  double path_gt_m = 0;
  double path_est_m = 0;
  std::optional<double> path_error_pct;

  double ate_rmse_m = 0;
  double ate_max_m = 0;
  // Camera orientation drift: the estimate turned so that its first orientation is the truth's,
  // the angle between each true and estimated orientation, degrees. Positions alone can be right
  // while the camera's orientation drifts, and every wall point placed from a frame (`locate`,
  // the maps) inherits that drift.
  double rot_rmse_deg = 0;
  double rot_max_deg = 0;
  Alignment alignment = Alignment::kSe3;
  std::optional<double> scale;  // Sim(3) alignment only: ground truth ≈ scale * estimate.

  std::optional<double> rpe_1m_pct;  // Unset when the run is shorter than the segment.

  // Set when junctions were evaluated (networks).
  std::optional<std::vector<JunctionDistance>> junction_distances;

  // Set when a simulated run's dense map was evaluated (`evaluate --dense-map`).
  std::optional<std::vector<DensePieceAgreement>> dense_map;
};

}  // namespace pipescope
