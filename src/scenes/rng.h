// A small seeded random generator for the procedural scenes: PCG32 (XSH-RR)
// seeded through splitmix64. Only integer arithmetic and exact float scaling,
// so a (seed, stream) pair gives the same numbers on every platform (the
// standard library's distributions are implementation-defined).
#pragma once

#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "mbrt/math.h"
#include "mbrt/splitmix.h"

namespace mbrt::scenes {

// Mixes two values into one (for deriving per-object seeds).
constexpr uint64_t mixSeed(uint64_t a, uint64_t b) {
  uint64_t s = a ^ (b * 0xD6E8FEB86659FD93ull + 0x632BE59BD9B4E019ull);
  splitmix64(s);
  return splitmix64(s);
}

class Rng {
 public:
  // `stream` selects an independent sequence for the same seed (one per
  // strand, per object...), so generation order does not matter.
  explicit Rng(uint64_t seed, uint64_t stream = 0) {
    uint64_t s = mixSeed(seed, stream);
    inc_ = (splitmix64(s) << 1) | 1u;
    state_ = 0;
    nextU32();
    state_ += splitmix64(s);
    nextU32();
  }

  uint32_t nextU32() {
    const uint64_t old = state_;
    state_ = old * 6364136223846793005ull + inc_;
    const uint32_t xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
    const uint32_t rot = uint32_t(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
  }

  // Uniform in [0,1): the top 24 bits, exactly representable in float.
  float uniform() { return float(nextU32() >> 8) * (1.0f / 16777216.0f); }
  float uniform(float lo, float hi) { return lo + (hi - lo) * uniform(); }
  // Uniform integer in [0, n) (multiply-shift; the tiny bias is irrelevant here).
  uint32_t below(uint32_t n) { return uint32_t((uint64_t(nextU32()) * n) >> 32); }

  // Uniform point in the unit ball (rejection from the cube).
  Vec3f inUnitBall() {
    for (;;) {
      Vec3f p{uniform(-1.0f, 1.0f), uniform(-1.0f, 1.0f), uniform(-1.0f, 1.0f)};  // braces: left to right
      if (dot(p, p) <= 1.0f) return p;
    }
  }
  // Uniform direction on the unit sphere.
  Vec3f unitVector() {
    for (;;) {
      Vec3f p{uniform(-1.0f, 1.0f), uniform(-1.0f, 1.0f), uniform(-1.0f, 1.0f)};
      const float d = dot(p, p);
      if (d > 1e-4f && d <= 1.0f) return p * (1.0f / std::sqrt(d));
    }
  }

  template <class T>
  void shuffle(std::vector<T>& v) {
    for (size_t i = v.size(); i > 1; --i) std::swap(v[i - 1], v[below(uint32_t(i))]);
  }

 private:
  uint64_t state_ = 0, inc_ = 1;
};

}  // namespace mbrt::scenes
