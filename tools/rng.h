// A small counter-based random generator for `mbrt trace --generate` (the
// camera is mbrt/camera.h's).
#pragma once

#include <cstdint>

#include "mbrt/splitmix.h"

namespace mbrt::tools {

// SplitMix64: seeded per pixel or per ray so results do not depend on the
// thread count.
class Rng {
 public:
  explicit Rng(uint64_t seed) : state_(seed) {}
  Rng(uint64_t seed, uint64_t a, uint64_t b = 0) : state_(seed) {
    state_ = next() ^ (a * kSplitMixGamma);
    state_ = next() ^ (b * 0xC2B2AE3D27D4EB4Full);
  }
  uint64_t next() { return splitmix64(state_); }
  // Uniform in [0,1).
  float uniform() { return toUnitFloat(next()); }

 private:
  uint64_t state_;
};

}  // namespace mbrt::tools
