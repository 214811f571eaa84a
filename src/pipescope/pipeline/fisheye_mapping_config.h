#pragma once

#include "pipescope/io/option_table.h"
#include "pipescope/pipeline/fisheye_mapping.h"

namespace pipescope {

// The keys of `pipescope map --config FILE` (all optional), each declared once: `--config` reads
// them, run.json records them, `pipescope map --list-keys` lists them. The radius comes from the
// dataset (pipe.inner_radius_m) or --radius.
const OptionTable<FisheyeMappingOptions>& FisheyeMappingOptionTable();

}  // namespace pipescope
