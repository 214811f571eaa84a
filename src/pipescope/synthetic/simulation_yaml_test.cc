#include "pipescope/synthetic/simulation_yaml.h"

#include <gtest/gtest.h>

#include "pipescope/synthetic/dataset_writer.h"
#include "pipescope/synthetic/presets.h"
#include "pipescope/util/atomic_file.h"
#include "pipescope/util/error.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

// What simulate writes reads back to the same config, key by key, keys set away from the
// preset's values included (a network route, a seed, the conditions' texture and noise).
TEST(SimulationYaml, ReadsBackWhatSimulateWrote) {
  SimulationConfig written = PresetConfig("fiberglass-network");
  for (const char* assignment :
       {"route=B", "seed=43", "texture_contrast=0.4", "noise_sigma=3", "frames=123",
        "speed_m_s=0.075", "specular_strength=0.6"}) {
    SetConfigValue(&written, assignment);
  }
  const auto dir = MakeTestDirectory("simulation_yaml");
  WriteTextFileAtomically(dir / "simulation.yaml", SimulationConfigYaml(written));
  const SimulationConfig read = ReadSimulationConfig(dir / "simulation.yaml");
  EXPECT_EQ(read.preset, "fiberglass-network");
  for (const ConfigKey& key : SimulationConfigKeys()) {
    EXPECT_EQ(GetConfigValue(read, key.name), GetConfigValue(written, key.name)) << key.name;
  }
  EXPECT_EQ(read.route, "B");
  EXPECT_EQ(read.seed, 43u);
}

TEST(SimulationYaml, BadFilesNameTheFileAndTheKey) {
  const auto dir = MakeTestDirectory("simulation_yaml_bad");
  const auto expect_error = [&](const std::string& text, const std::string& what) {
    WriteTextFileAtomically(dir / "simulation.yaml", text);
    try {
      ReadSimulationConfig(dir / "simulation.yaml");
      ADD_FAILURE() << "no error for: " << text;
    } catch (const InputError& error) {
      const std::string message = error.what();
      EXPECT_NE(message.find("simulation.yaml"), std::string::npos) << message;
      EXPECT_NE(message.find(what), std::string::npos) << message;
    }
  };
  expect_error("preset: fiberglass-network\nno_such_key: 1\n", "no_such_key");
  expect_error("preset: no-such-preset\n", "no-such-preset");
  expect_error("frames: 10\n", "preset");
  expect_error("preset: fiberglass-network\nnoise_sigma: [1, 2]\n", "noise_sigma");
  expect_error("preset: fiberglass-network\nnoise_sigma: loud\n", "noise_sigma");
  expect_error("[1, 2", "YAML");
  EXPECT_THROW(ReadSimulationConfig(dir / "missing.yaml"), InputError);
}

}  // namespace
}  // namespace pipescope
