#pragma once

#include "pipescope/io/option_table.h"
#include "pipescope/pipeline/dense_vo.h"

namespace pipescope {

// The keys of `pipescope odometry --config FILE` for the dense methods (all optional), each
// declared once: `--config` reads them, run.json records them, `pipescope odometry --list-keys`
// lists them. The method itself comes from --method.
const OptionTable<DenseOdometerOptions>& DenseVoOptionTable();

}  // namespace pipescope
