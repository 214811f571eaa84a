// Fuzzes ReadCamera over its three formats (pipescope camera.yaml, OpenCV FileStorage YAML/XML
// or ROS-style YAML, Kalibr camchain), chosen by content as for a user's file. Bad input must be
// an InputError, nothing else.
#include <cstddef>
#include <cstdint>

#include "fuzz/fuzz_input.h"
#include "pipescope/camera/camera_io.h"
#include "pipescope/util/error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path path = pipescope::fuzz::WriteFuzzInput(data, size, "camera.yaml");
  try {
    pipescope::ReadCamera(path);
  } catch (const pipescope::InputError&) {
  }
  return 0;
}
