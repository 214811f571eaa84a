#pragma once

#include "pipescope/io/option_table.h"
#include "pipescope/pipeline/ekf_vo.h"

namespace pipescope {

// The keys of `pipescope odometry --method ekf --config FILE` (all optional), each declared
// once: `--config` reads them, run.json records them, `--list-keys` lists them.
const OptionTable<EkfVoOptions>& EkfVoOptionTable();

}  // namespace pipescope
