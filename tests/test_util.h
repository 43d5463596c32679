// Helpers shared by the tests: small random scenes and ray generators.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <random>
#include <vector>

#include "mbrt/accel.h"
#include "mbrt/scene.h"

#ifndef MBRT_DEFAULT_TEST_SCALE
#define MBRT_DEFAULT_TEST_SCALE 1.0
#endif

namespace mbrt::test {

// How much of its full size a heavy test runs at: MBRT_TEST_SCALE from the
// environment, else the build's default (1; 0.1 in sanitizer builds, see
// cmake/Sanitize.cmake). Heavy tests multiply ray and primitive counts by it.
inline double testScale() {
  static const double scale = [] {
    double s = MBRT_DEFAULT_TEST_SCALE;
    if (const char* e = std::getenv("MBRT_TEST_SCALE")) {
      char* end = nullptr;
      const double v = std::strtod(e, &end);
      if (end != e && v > 0.0 && v <= 1000.0) s = v;
    }
    return s;
  }();
  return scale;
}
// `n` scaled, at least `atLeast`.
inline size_t scaled(size_t n, size_t atLeast = 1) {
  return std::max(atLeast, size_t(double(n) * testScale() + 0.5));
}

inline std::unique_ptr<Accel> buildKind(const Scene& scene, AccelKind kind, int branching = 8) {
  BuildOptions o;
  o.kind = kind;
  o.branching = branching;
  return Accel::build(scene, o);
}

// `count` random triangles of size ~`extent` in [-1,1]^3, each moving along a
// random path with `steps` steps.
inline uint32_t addRandomMovingTriangles(Scene& scene, std::mt19937& rng, uint32_t count, uint32_t steps,
                                         float extent = 0.2f, float motion = 0.3f, TimeRange range = {}) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<Triangle> tris;
  std::vector<std::vector<Vec3f>> pos(steps);
  for (uint32_t i = 0; i < count; ++i) {
    const Vec3f c{u(rng), u(rng), u(rng)};
    Vec3f v[3];
    for (auto& p : v) p = c + Vec3f{u(rng), u(rng), u(rng)} * extent;
    Vec3f offset{0.0f};
    for (uint32_t s = 0; s < steps; ++s) {
      for (const auto& p : v) pos[s].push_back(p + offset);
      offset += Vec3f{u(rng), u(rng), u(rng)} * motion;
    }
    tris.push_back({3 * i, 3 * i + 1, 3 * i + 2});
  }
  return scene.addTriangleMesh(std::move(tris), std::move(pos), range);
}

inline Ray randomRay(std::mt19937& rng, float time) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  Ray r;
  r.org = Vec3f{u(rng), u(rng), u(rng)} * 3.0f;
  const Vec3f target{u(rng) * 0.8f, u(rng) * 0.8f, u(rng) * 0.8f};
  r.dir = target - r.org;
  r.time = time;
  return r;
}

}  // namespace mbrt::test
