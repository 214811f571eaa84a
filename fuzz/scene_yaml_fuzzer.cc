// Fuzzes the reading of a scene.yaml, whose junctions `pipescope evaluate --scene` reads
// (ReadSceneJunctions); the seeds are whole scene files as the simulator writes them. Bad input
// must be an InputError, nothing else.
#include <cstddef>
#include <cstdint>

#include "fuzz/fuzz_input.h"
#include "pipescope/io/junctions.h"
#include "pipescope/util/error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path path = pipescope::fuzz::WriteFuzzInput(data, size, "scene.yaml");
  try {
    pipescope::ReadSceneJunctions(path);
  } catch (const pipescope::InputError&) {
  }
  return 0;
}
