// A small counter-based random generator for `mbrt trace --generate` (the
// camera is mbrt/camera.h's).
#pragma once

#include <cstdint>

namespace mbrt::tools {

// SplitMix64: seeded per pixel or per ray so results do not depend on the
// thread count.
class Rng {
 public:
  explicit Rng(uint64_t seed) : state_(seed) {}
  Rng(uint64_t seed, uint64_t a, uint64_t b = 0) : state_(seed) {
    state_ = next() ^ (a * 0x9E3779B97F4A7C15ull);
    state_ = next() ^ (b * 0xC2B2AE3D27D4EB4Full);
  }
  uint64_t next() {
    uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  // Uniform in [0,1).
  float uniform() { return float(next() >> 40) * (1.0f / 16777216.0f); }

 private:
  uint64_t state_;
};

}  // namespace mbrt::tools
