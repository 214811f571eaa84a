// Fuzzes ReadDatasetManifest. The manifest is written into a dataset folder that holds every file
// a manifest may name (empty: the reader only checks that they exist), so that inputs naming them
// get past the existence checks to the later keys. Bad input must be an InputError, nothing else.
#include <cstddef>
#include <cstdint>
#include <fstream>

#include "fuzz/fuzz_input.h"
#include "pipescope/io/dataset.h"
#include "pipescope/util/error.h"

namespace {

void MakeDatasetFolder() {
  const std::filesystem::path& dir = pipescope::fuzz::FuzzDirectory();
  std::filesystem::create_directories(dir / "images");
  for (const char* name : {"camera.yaml", "video.mp4", "timestamps.txt", "gain_mask.png",
                           "groundtruth.tum", "scene.yaml"}) {
    std::ofstream(dir / name);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const bool made = (MakeDatasetFolder(), true);
  (void)made;
  const std::filesystem::path path = pipescope::fuzz::WriteFuzzInput(data, size, "dataset.yaml");
  try {
    pipescope::ReadDatasetManifest(path);
  } catch (const pipescope::InputError&) {
  }
  return 0;
}
