// A hand-made scene with everything at once: meshes with 1, 2 and 5 steps,
// partial time ranges, round segments, and instances nested two deep with
// moving matrix keys (depth 1: the middle scene holds no instance, for
// Embree, which nests one level).
#pragma once

#include <memory>
#include <random>

#include "mbrt/scenes.h"
#include "test_util.h"

namespace mbrt::test {

inline ProceduralScene mixedScene(int depth = 2) {
  std::mt19937 rng(21);
  auto leaf = std::make_shared<Scene>();
  test::addRandomMovingTriangles(*leaf, rng, 60, 3, 0.15f, 0.1f);
  auto middle = std::make_shared<Scene>();
  test::addRandomMovingTriangles(*middle, rng, 40, 2, 0.15f, 0.2f);
  if (depth >= 2)
    middle->addInstance(leaf, {Affine3f::translate({0.5f, 0, 0}) * Affine3f::scale(Vec3f(0.4f)),
                               Affine3f::translate({0.6f, 0.1f, 0}) * Affine3f::rotate({0, 1, 0}, 0.7f) *
                                   Affine3f::scale(Vec3f(0.4f))});
  auto top = std::make_shared<Scene>();
  test::addRandomMovingTriangles(*top, rng, 200, 1, 0.2f, 0.0f);
  test::addRandomMovingTriangles(*top, rng, 200, 2, 0.2f, 0.3f);
  test::addRandomMovingTriangles(*top, rng, 200, 5, 0.2f, 0.2f);
  test::addRandomMovingTriangles(*top, rng, 100, 3, 0.2f, 0.3f, {0.25f, 0.75f});
  test::addRandomMovingTriangles(*top, rng, 100, 4, 0.2f, 0.3f, {0.6f, 1.0f});
  {
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::vector<Segment> segs;
    std::vector<std::vector<Vec3f>> steps(3);
    std::vector<float> radii;
    for (uint32_t i = 0; i < 150; ++i) {
      const Vec3f a{u(rng), u(rng), u(rng)}, b = a + Vec3f{u(rng), u(rng), u(rng)} * 0.2f;
      for (uint32_t s = 0; s < 3; ++s) {
        const Vec3f off = Vec3f{u(rng), u(rng), u(rng)} * 0.1f;
        steps[s].push_back(a + off);
        steps[s].push_back(b + off);
      }
      radii.push_back(0.01f + 0.02f * std::fabs(u(rng)));
      radii.push_back(0.01f + 0.02f * std::fabs(u(rng)));
      segs.push_back({2 * i, 2 * i + 1});
    }
    top->addSegments(std::move(segs), std::move(steps), std::move(radii));
  }
  top->addInstance(middle, {Affine3f::translate({-0.5f, 0.3f, 0}), Affine3f::translate({-0.3f, 0.2f, 0.1f}),
                            Affine3f::translate({-0.4f, 0.0f, 0.3f}) * Affine3f::rotate({0, 0, 1}, 1.0f)},
                   {0.0f, 1.0f});
  top->addInstance(middle, {Affine3f::translate({0.4f, -0.5f, 0}) * Affine3f::scale(Vec3f(0.7f))}, {0.1f, 0.9f});
  ProceduralScene ps;
  ps.name = "mixed";
  ps.scene = top;
  ps.camera = frameBox(Box3f({-1.2f, -1.2f, -1.2f}, {1.2f, 1.2f, 1.2f}));
  return ps;
}

}  // namespace mbrt::test
