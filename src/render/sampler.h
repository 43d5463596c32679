// Counter-based random numbers: every value is a hash of (seed, pixel,
// sample, dimension), so a pixel's samples do not depend on which thread
// renders it, nor on the order of tiles.
#pragma once

#include <cmath>
#include <cstdint>

#include "mbrt/splitmix.h"

namespace mbrt::renderer {

// One pixel's key: sample-independent values (e.g. a per-pixel rotation of
// the stratified times) come from here.
inline uint64_t pixelKey(uint64_t seed, uint64_t pixel) {
  return mix64(mix64(seed + kSplitMixGamma) ^ (pixel * 0xD1B54A32D192ED03ull));
}

// The stream of one camera sample of one pixel: next() gives dimension 0, 1, ...
class Sampler {
 public:
  Sampler(uint64_t seed, uint64_t pixel, uint32_t sample)
      : key_(mix64(pixelKey(seed, pixel) ^ (uint64_t(sample) * 0x8CB92BA72F3D8DD7ull + 0x632BE59BD9B4E019ull))) {}

  float next() { return toUnitFloat(mix64(key_ + (++dim_) * kSplitMixGamma)); }
  uint32_t dimension() const { return dim_; }

 private:
  uint64_t key_;
  uint32_t dim_ = 0;
};

// Sample s of n stratified over [0,1), the strata rotated per pixel
// (Cranley-Patterson) so that neighbouring pixels see different times.
inline float stratified(int s, int n, float jitter, float rotation) {
  float u = (float(s) + jitter) / float(n) + rotation;
  u -= std::floor(u);
  return u < 1.0f ? u : 0.99999994f;
}

}  // namespace mbrt::renderer
