#pragma once

#include "pipescope/io/option_table.h"
#include "pipescope/pipeline/sparse_vo.h"

namespace pipescope {

// The keys of `pipescope odometry --method sparse --config FILE` (all optional, defaults from
// 000 §5 unless the help says otherwise), each declared once: `--config` reads them, run.json
// records them, `pipescope odometry --list-keys` lists them.
const OptionTable<SparseVoOptions>& SparseVoOptionTable();

}  // namespace pipescope
