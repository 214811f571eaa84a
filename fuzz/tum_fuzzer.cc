// Fuzzes ReadTumTrajectory: bad input must be an InputError, nothing else.
#include <cstddef>
#include <cstdint>

#include "fuzz/fuzz_input.h"
#include "pipescope/io/trajectory.h"
#include "pipescope/util/error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path path = pipescope::fuzz::WriteFuzzInput(data, size, "trajectory.tum");
  try {
    pipescope::ReadTumTrajectory(path);
  } catch (const pipescope::InputError&) {
  }
  return 0;
}
