#include "pipescope/estimation/loop_candidates.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <string>

#include "pipescope/util/error.h"

namespace pipescope {
namespace {

const char* TurnName(int turn) { return turn > 0 ? "left" : turn < 0 ? "right" : "straight"; }

// The centroid of the junction at section end `end` as `pass` knows it, if it does.
std::optional<Eigen::Vector3d> CentroidAtEnd(const PassJunctions& pass, int end) {
  return pass.pass.toward_end == end ? pass.end_centroid : pass.start_centroid;
}

// A key frame of a pass and its distance l to the reference junction's centroid.
struct KeyFrameDistance {
  double distance_m;
  int key_frame;
};

std::vector<KeyFrameDistance> DistancesTo(const Eigen::Vector3d& centroid,
                                          const std::vector<int>& key_frames,
                                          const std::vector<Eigen::Vector3d>& positions) {
  std::vector<KeyFrameDistance> distances;
  for (int k : key_frames) distances.push_back({(positions[k] - centroid).norm(), k});
  std::sort(distances.begin(), distances.end(),
            [](const KeyFrameDistance& a, const KeyFrameDistance& b) {
              return a.distance_m < b.distance_m;
            });
  return distances;
}

// The entry of `sorted` (by distance, non-empty) nearest in distance to `distance_m`.
const KeyFrameDistance& NearestInDistance(const std::vector<KeyFrameDistance>& sorted,
                                          double distance_m) {
  auto above = std::lower_bound(
      sorted.begin(), sorted.end(), distance_m,
      [](const KeyFrameDistance& entry, double d) { return entry.distance_m < d; });
  if (above == sorted.end()) return sorted.back();
  if (above == sorted.begin()) return *above;
  const auto below = std::prev(above);
  return distance_m - below->distance_m <= above->distance_m - distance_m ? *below : *above;
}

// At most `max_pairs` of `matched` (sorted by the earlier key frame's distance), the ones nearest
// to evenly spaced distances over [low, high]: loop closures along the whole overlap constrain
// the section's direction as well as its place.
std::vector<LoopCandidate> SpreadEvenly(const std::vector<LoopCandidate>& matched, double low,
                                        double high, int max_pairs) {
  if (static_cast<int>(matched.size()) <= max_pairs) return matched;
  std::vector<LoopCandidate> spread;
  int last_taken = -1;
  for (int k = 0; k < max_pairs; ++k) {
    const double target = low + (k + 0.5) * (high - low) / max_pairs;
    int nearest = 0;
    for (int m = 1; m < static_cast<int>(matched.size()); ++m) {
      if (std::abs(matched[m].earlier_distance_m - target) <
          std::abs(matched[nearest].earlier_distance_m - target)) {
        nearest = m;
      }
    }
    if (nearest == last_taken) continue;
    spread.push_back(matched[nearest]);
    last_taken = nearest;
  }
  return spread;
}

// The candidates between passes a (earlier) and b of the same section, about the centroid of
// the junction at section end `end`.
std::vector<LoopCandidate> PairPasses(const std::vector<KeyFrameDistance>& a,
                                      const std::vector<KeyFrameDistance>& b,
                                      const LoopCandidateOptions& options) {
  if (a.empty() || b.empty()) return {};
  const double low = std::max(a.front().distance_m, b.front().distance_m);
  const double high = std::min(a.back().distance_m, b.back().distance_m);
  std::vector<LoopCandidate> matched;
  for (const KeyFrameDistance& earlier : a) {
    if (earlier.distance_m < low || earlier.distance_m > high) continue;
    const KeyFrameDistance& later = NearestInDistance(b, earlier.distance_m);
    const double tolerance =
        std::max(options.tolerance_m, options.tolerance_fraction * earlier.distance_m);
    if (std::abs(later.distance_m - earlier.distance_m) > tolerance) continue;
    matched.push_back({earlier.key_frame, later.key_frame, earlier.distance_m, later.distance_m});
  }
  return SpreadEvenly(matched, low, high, options.max_pairs);
}

}  // namespace

int TurnDirection(const Eigen::Vector3d& axis_in, const Eigen::Vector3d& axis_out,
                  const Eigen::Vector3d& up, double straight_below_rad) {
  for (const Eigen::Vector3d* v : {&axis_in, &axis_out, &up}) {
    if (!v->allFinite() || v->norm() == 0.0) {
      throw InputError("TurnDirection: the axes and up must be finite and non-zero");
    }
  }
  const Eigen::Vector3d cross = axis_in.normalized().cross(axis_out.normalized());
  const double angle = std::atan2(cross.norm(), axis_in.normalized().dot(axis_out.normalized()));
  if (angle < straight_below_rad) return 0;
  return cross.dot(up) > 0.0 ? 1 : -1;
}

std::vector<SectionPass> NameSectionPasses(const PipeNetwork& network, const SectionPass& start,
                                           const std::vector<int>& turns) {
  const int sections = static_cast<int>(network.section_ends.size());
  auto check_pass = [sections](const SectionPass& pass, const std::string& what) {
    if (pass.section < 0 || pass.section >= sections || pass.toward_end < 0 ||
        pass.toward_end > 1) {
      throw InputError(what + ": section " + std::to_string(pass.section) + " end " +
                       std::to_string(pass.toward_end) + " is not in the network of " +
                       std::to_string(sections) + " sections");
    }
  };
  check_pass(start, "the start pass");
  std::vector<SectionPass> passes = {start};
  for (int t = 0; t < static_cast<int>(turns.size()); ++t) {
    const SectionPass& current = passes.back();
    const SectionEndExits& exits = network.section_ends[current.section][current.toward_end];
    const SectionExit& exit = turns[t] > 0   ? exits.left
                              : turns[t] < 0 ? exits.right
                                             : exits.straight;
    const std::string turn_name = "turn " + std::to_string(t) + " (" + TurnName(turns[t]) +
                                  ") at end " + std::to_string(current.toward_end) +
                                  " of section " + std::to_string(current.section);
    if (exit.section < 0) throw InputError(turn_name + " leads into no pipe");
    // Entering a section through one end, the robot drives towards the other.
    const SectionPass next = {exit.section, 1 - exit.entered_end};
    check_pass(next, turn_name);
    passes.push_back(next);
  }
  return passes;
}

std::vector<LoopCandidate> SelectLoopCandidates(
    const std::vector<Eigen::Vector3d>& key_frame_positions, const std::vector<int>& key_frame_pass,
    const std::vector<PassJunctions>& passes, const LoopCandidateOptions& options) {
  if (key_frame_positions.size() != key_frame_pass.size()) {
    throw InputError("SelectLoopCandidates: " + std::to_string(key_frame_positions.size()) +
                     " key frame positions but " + std::to_string(key_frame_pass.size()) +
                     " pass indices");
  }
  const int pass_count = static_cast<int>(passes.size());
  std::vector<std::vector<int>> key_frames_of_pass(pass_count);
  for (int k = 0; k < static_cast<int>(key_frame_pass.size()); ++k) {
    const int pass = key_frame_pass[k];
    if (pass == -1) continue;
    if (pass < -1 || pass >= pass_count) {
      throw InputError("SelectLoopCandidates: key frame " + std::to_string(k) + " is in pass " +
                       std::to_string(pass) + " of " + std::to_string(pass_count));
    }
    key_frames_of_pass[pass].push_back(k);
  }

  std::vector<LoopCandidate> candidates;
  for (int a = 0; a < pass_count; ++a) {
    for (int b = a + 1; b < pass_count; ++b) {
      if (passes[a].pass.section != passes[b].pass.section) continue;
      // 001 measures l to the junction at the end of the section; the one the earlier pass ends
      // at unless the later pass cannot place it (it started from a dead end).
      for (int end : {passes[a].pass.toward_end, 1 - passes[a].pass.toward_end}) {
        const std::optional<Eigen::Vector3d> centroid_a = CentroidAtEnd(passes[a], end);
        const std::optional<Eigen::Vector3d> centroid_b = CentroidAtEnd(passes[b], end);
        if (!centroid_a || !centroid_b) continue;
        const std::vector<LoopCandidate> pairs = PairPasses(
            DistancesTo(*centroid_a, key_frames_of_pass[a], key_frame_positions),
            DistancesTo(*centroid_b, key_frames_of_pass[b], key_frame_positions), options);
        candidates.insert(candidates.end(), pairs.begin(), pairs.end());
        break;
      }
    }
  }
  return candidates;
}

}  // namespace pipescope
