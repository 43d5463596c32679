// The small moving scene that hostile rays are traced against, in
// tests/test_robustness.cpp and in the fuzz target fuzz_ray_file: 40
// triangles in a grid, each moving its own way over 3 steps, and one round
// segment with a partial time range.
#pragma once

#include <vector>

#include "mbrt/scene.h"

namespace mbrt::test {

inline Scene hostileRayScene() {
  Scene scene;
  std::vector<Triangle> tris;
  std::vector<std::vector<Vec3f>> steps(3);
  for (uint32_t i = 0; i < 40; ++i) {
    const float x = float(i % 8) * 0.25f - 1.0f, y = float(i / 8) * 0.4f - 1.0f;
    for (uint32_t s = 0; s < 3; ++s) {
      const float dz = 0.3f * float(s) * float(i % 3);
      steps[s].push_back({x, y, dz});
      steps[s].push_back({x + 0.3f, y, dz + 0.1f});
      steps[s].push_back({x, y + 0.5f, dz - 0.1f});
    }
    tris.push_back({3 * i, 3 * i + 1, 3 * i + 2});
  }
  scene.addTriangleMesh(std::move(tris), std::move(steps));
  scene.addSegments({{0, 1}}, {{{0, 0, 1}, {1, 1, 1}}}, {0.1f, 0.2f}, {0.2f, 0.8f});
  return scene;
}

}  // namespace mbrt::test
