#pragma once

#include <cstdint>

namespace pipescope {

// SplitMix64's finaliser: a well-mixed 64-bit value from (seed, stream, index), so independent
// random streams (motion, texture, per-frame noise) all derive from one user seed and do not
// depend on the order in which they are drawn.
inline std::uint64_t MixSeed(std::uint64_t seed, std::uint64_t stream, std::uint64_t index = 0) {
  std::uint64_t z = seed * 0x9E3779B97F4A7C15ULL + (stream + 1) * 0xD1B54A32D192ED03ULL + index;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

}  // namespace pipescope
