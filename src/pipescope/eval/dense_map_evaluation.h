#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "pipescope/eval/dense_map_agreement.h"
#include "pipescope/io/trajectory.h"
#include "pipescope/synthetic/simulation.h"

namespace pipescope {


// Scores every piece of the dense map in the `map` run folder `run` (run.json's dense_map,
// keyframes.tum and the dense_section_N.png mosaics, each the section's pieces stacked in
// their order) against the albedo of the simulation that rendered its dataset
// (CorrelateWithAlbedo). Each row of a piece goes into the scene through the true
// (`ground_truth`, the pose within max_dt_s of its time) and estimated pose of the piece's key
// frame nearest it along the axis, whose true position is where its albedo is looked up from
// (SimulatedAlbedoUnderGrid). Throws InputError naming the file for a run without a dense map,
// a mosaic that does not hold its pieces, or a key frame without a true pose.
std::vector<DensePieceAgreement> EvaluateDenseMap(const std::filesystem::path& run,
                                                  const Trajectory& ground_truth,
                                                  const Simulation& simulation, double max_dt_s,
                                                  const DenseMapAgreementOptions& options = {});

}  // namespace pipescope
