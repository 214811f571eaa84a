// Fuzzes the junctions.yaml reader of a run (ReadEstimatedJunctions) and, on the same text, the
// scene reader (ReadSceneJunctions): bad input must be an InputError, nothing else.
#include <cstddef>
#include <cstdint>

#include "fuzz/fuzz_input.h"
#include "pipescope/io/junctions.h"
#include "pipescope/util/error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path path = pipescope::fuzz::WriteFuzzInput(data, size, "junctions.yaml");
  try {
    pipescope::ReadEstimatedJunctions(path);
  } catch (const pipescope::InputError&) {
  }
  try {
    pipescope::ReadSceneJunctions(path);
  } catch (const pipescope::InputError&) {
  }
  return 0;
}
