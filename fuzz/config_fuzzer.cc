// Fuzzes the option tables' `--config` reader (OptionTable::ApplyYamlFile) of odometry (sparse
// and dense), map and the simulator, then the simulator's checks and `--set key=value` on the
// same text. Bad input must be an InputError, nothing else.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz/fuzz_input.h"
#include "pipescope/pipeline/dense_vo_config.h"
#include "pipescope/pipeline/fisheye_mapping_config.h"
#include "pipescope/pipeline/sparse_vo_config.h"
#include "pipescope/synthetic/simulation_config.h"
#include "pipescope/util/error.h"

namespace pipescope {

// Link-time stand-ins for the per-method defaults of the odometry and mapping stacks, which the
// Options structs' member initialisers and the dense table's run.json view call. This target
// compiles the option tables alone: the libraries behind these four functions are most of
// pipescope, slow to build with the sanitizers, and the tables' reading does not depend on the
// defaults (no table checks one key against another).
RegionHarrisOptions SparseVoRegionHarrisOptions() { return {}; }
RegionHarrisOptions FisheyeRegionHarrisOptions() { return {}; }
WindowAdjustmentOptions SparseVoWindowOptions() { return {}; }
double KeyFrameShiftFraction(DenseMethod) { return 0.1; }

}  // namespace pipescope

namespace {

// Applies the file to a default Options and, when that succeeds, writes the run.json view.
template <typename Options>
void Apply(const pipescope::OptionTable<Options>& table, const std::filesystem::path& path,
           Options* options) {
  try {
    table.ApplyYamlFile(path, options);
    table.ToJson(*options);
  } catch (const pipescope::InputError&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path path = pipescope::fuzz::WriteFuzzInput(data, size, "config.yaml");
  pipescope::SparseVoOptions sparse;
  Apply(pipescope::SparseVoOptionTable(), path, &sparse);
  pipescope::DenseOdometerOptions dense;
  Apply(pipescope::DenseVoOptionTable(), path, &dense);
  pipescope::FisheyeMappingOptions mapping;
  Apply(pipescope::FisheyeMappingOptionTable(), path, &mapping);
  pipescope::SimulationConfig simulation;
  Apply(pipescope::SimulationOptionTable(), path, &simulation);
  try {
    pipescope::ValidateConfig(simulation);
  } catch (const pipescope::InputError&) {
  }
  try {
    pipescope::SetConfigValue(&simulation, std::string(reinterpret_cast<const char*>(data), size));
  } catch (const pipescope::InputError&) {
  }
  return 0;
}
