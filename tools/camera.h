// Pinhole camera rays and a small counter-based random generator for
// `mbrt trace --generate` (the renderer has its own: mbrt/render.h).
#pragma once

#include <cmath>
#include <cstdint>

#include "mbrt/ray.h"
#include "mbrt/scenes.h"

namespace mbrt::tools {

class PinholeCamera {
 public:
  PinholeCamera(const CameraSpec& spec, float aspect) : eye_(spec.eye) {
    w_ = normalize(spec.eye - spec.target);
    u_ = normalize(cross(spec.up, w_));
    v_ = cross(w_, u_);
    halfH_ = std::tan(0.5f * spec.verticalFovDegrees * 3.14159265f / 180.0f);
    halfW_ = aspect * halfH_;
  }

  // (x, y) in [0,1]^2 over the image, y = 0 at the top.
  Ray ray(float x, float y, float time) const {
    Ray r;
    r.org = eye_;
    r.dir = normalize(u_ * ((2.0f * x - 1.0f) * halfW_) + v_ * ((1.0f - 2.0f * y) * halfH_) - w_);
    r.tnear = 0.0f;
    r.tfar = kInf;
    r.time = time;
    return r;
  }

 private:
  Vec3f eye_, u_, v_, w_;
  float halfW_ = 1.0f, halfH_ = 1.0f;
};

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
