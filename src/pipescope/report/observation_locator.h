#pragma once

#include <vector>

#include "pipescope/camera/camera.h"
#include "pipescope/report/observations.h"
#include "pipescope/report/run_files.h"

namespace pipescope {

// Places one observation on the wall of the run's pipe: its centre (distance, clock, section),
// and for a box the extent of distance and clock over its border (sampled every few pixels).
// Not located (with the reason) when its frame has no pose or its centre has no ray to the wall.
// Map runs are refused (InputError): their camera orientations drift too far (docs/report.md).
LocatedObservation LocateObservation(const RunFiles& run, const Camera& camera,
                                     const Observation& observation);

}  // namespace pipescope
