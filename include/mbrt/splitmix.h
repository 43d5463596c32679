// SplitMix64 (Steele, Lea and Flood, "Fast splittable pseudorandom number
// generators", OOPSLA 2014), the one 64-bit mix of mbrt: the procedural
// scenes' seeding, the renderer's and the bench's counter-based random
// numbers and the command's random rays all hash with it, so that every
// value depends on its (seed, index) alone, not on threads or order.
#pragma once

#include <cstdint>

namespace mbrt {

inline constexpr uint64_t kSplitMixGamma = 0x9E3779B97F4A7C15ull;

// The finalizer: a bijective 64-bit mix with good avalanche.
constexpr uint64_t mix64(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

// One step of the generator: advances `state` by the golden gamma and
// returns its mix.
constexpr uint64_t splitmix64(uint64_t& state) { return mix64(state += kSplitMixGamma); }

// The top 24 bits as a float in [0, 1).
constexpr float toUnitFloat(uint64_t bits) { return float(bits >> 40) * (1.0f / 16777216.0f); }

}  // namespace mbrt
