// Scenes for the `auto` tests: lat-long blobs moving rigidly (whole meshes
// and connected pieces), deforming, static with a filter, nearly rigid with
// noise of a given relative size, segments and a user instance whose scene
// holds a rigid mesh itself.
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "mbrt/scenes.h"

namespace mbrt::test {

struct MeshParts {
  std::vector<Triangle> triangles;
  std::vector<Vec3f> vertices;
};

// A lumpy lat-long sphere appended to `m` (a connected piece of its own).
inline void addBlob(MeshParts& m, Vec3f centre, float radius, int n, float lumps) {
  const uint32_t base = uint32_t(m.vertices.size());
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j < 2 * n; ++j) {
      const float th = 3.14159265f * float(i) / float(n), ph = 3.14159265f * float(j) / float(n);
      const Vec3f d{std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph)};
      const float r = radius * (1.0f + lumps * std::sin(3.0f * th + 1.0f) * std::cos(2.0f * ph));
      m.vertices.push_back(centre + d * r);
    }
  auto at = [&](int i, int j) { return base + uint32_t(i * 2 * n + (j % (2 * n))); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < 2 * n; ++j) {
      if (i > 0) m.triangles.push_back({at(i, j), at(i + 1, j), at(i, j + 1)});
      if (i + 1 < n) m.triangles.push_back({at(i, j + 1), at(i + 1, j), at(i + 1, j + 1)});
    }
}

inline Affine3f turnAbout(Vec3f pivot, Vec3f axis, float angle) {
  return Affine3f::translate(pivot) * Affine3f::rotate(axis, angle) * Affine3f::translate(pivot * -1.0f);
}

// Steps of vertices moved by `keys`, plus (for `deforming` vertices) a wave,
// plus relative noise of size `noise` (of `scale`).
inline std::vector<std::vector<Vec3f>> movedSteps(const std::vector<Vec3f>& rest, const std::vector<Affine3f>& keys,
                                                  uint32_t deformFrom, float noise, float scale, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<std::vector<Vec3f>> steps;
  for (size_t k = 0; k < keys.size(); ++k) {
    std::vector<Vec3f> s;
    for (uint32_t v = 0; v < rest.size(); ++v) {
      Vec3f p = keys[k].xfmPoint(rest[v]);
      if (v >= deformFrom) p = p + Vec3f{0.0f, 0.08f * std::sin(6.0f * rest[v].x + float(k)), 0.0f};
      if (noise > 0.0f && k > 0) p = p + Vec3f{u(rng), u(rng), u(rng)} * (noise * scale);
      s.push_back(p);
    }
    steps.push_back(std::move(s));
  }
  return steps;
}

inline std::vector<Affine3f> turnKeys(uint32_t steps, Vec3f pivot, Vec3f axis, float turns, Vec3f drift = {}) {
  std::vector<Affine3f> keys;
  for (uint32_t k = 0; k < steps; ++k) {
    const float f = steps == 1 ? 0.0f : float(k) / float(steps - 1);
    keys.push_back(Affine3f::translate(drift * f) * turnAbout(pivot, axis, 6.2831853f * turns * f));
  }
  return keys;
}

// Geometry ids: 0 rigid blob [0.1, 0.9] (mask 1), 1 rigid piece + deforming
// piece, 2 deforming, 3 static with filter, 4 nearly rigid (noise), 5
// segments, 6 rigid with filter, 7 user instance (its scene: a rigid blob
// and a static one).
inline ProceduralScene autoTestScene(float noise = 0.0f, int n = 10) {
  auto top = std::make_shared<Scene>();
  {
    MeshParts m;
    addBlob(m, {-0.6f, 0.4f, 0.0f}, 0.3f, n, 0.2f);
    top->addTriangleMesh(m.triangles, movedSteps(m.vertices, turnKeys(9, {-0.5f, 0.4f, 0}, {0.2f, 1, 0.1f}, 1.5f), ~0u, 0, 1, 1),
                         {0.1f, 0.9f});
    top->setMask(0, 1u);
  }
  {
    MeshParts m;
    addBlob(m, {0.5f, 0.5f, 0.0f}, 0.25f, n, 0.1f);
    const uint32_t deformFrom = uint32_t(m.vertices.size());
    addBlob(m, {0.5f, -0.1f, 0.1f}, 0.25f, n, 0.0f);
    top->addTriangleMesh(m.triangles, movedSteps(m.vertices, turnKeys(5, {0.5f, 0.2f, 0}, {1, 0.3f, 0}, 0.4f), deformFrom, 0, 1, 2));
  }
  {
    MeshParts m;
    addBlob(m, {0.0f, -0.6f, 0.2f}, 0.3f, n, 0.15f);
    top->addTriangleMesh(m.triangles, movedSteps(m.vertices, std::vector<Affine3f>(4), 0, 0, 1, 3));
  }
  {
    MeshParts m;
    addBlob(m, {0.0f, 0.0f, -0.7f}, 0.5f, n, 0.0f);
    top->addTriangleMesh(m.triangles, std::vector<std::vector<Vec3f>>{m.vertices});
  }
  {
    MeshParts m;
    addBlob(m, {-0.5f, -0.4f, 0.3f}, 0.25f, n, 0.25f);
    top->addTriangleMesh(m.triangles,
                         movedSteps(m.vertices, turnKeys(6, {-0.5f, -0.4f, 0.3f}, {0, 0, 1}, 0.7f), ~0u, noise, 0.5f, 4));
  }
  {
    std::vector<Segment> segs;
    std::vector<std::vector<Vec3f>> steps(3);
    std::vector<float> radii;
    for (uint32_t i = 0; i < 20; ++i) {
      const Vec3f a{-0.9f + 0.09f * float(i), 0.9f, 0.3f};
      for (uint32_t s = 0; s < 3; ++s) {
        steps[s].push_back(a + Vec3f{0.05f * float(s), 0, 0});
        steps[s].push_back(a + Vec3f{0.02f, -0.2f, 0.05f * float(s)});
      }
      radii.push_back(0.01f);
      radii.push_back(0.015f);
      segs.push_back({2 * i, 2 * i + 1});
    }
    top->addSegments(segs, steps, radii);
  }
  {
    MeshParts m;
    addBlob(m, {0.7f, -0.6f, -0.2f}, 0.2f, n, 0.2f);
    top->addTriangleMesh(m.triangles, movedSteps(m.vertices, turnKeys(3, {0.7f, -0.6f, 0}, {0, 1, 0}, 0.3f), ~0u, 0, 1, 5));
  }
  {
    auto child = std::make_shared<Scene>();
    MeshParts a, b;
    addBlob(a, {0.0f, 0.0f, 0.0f}, 0.4f, n, 0.2f);
    child->addTriangleMesh(a.triangles, movedSteps(a.vertices, turnKeys(7, {0.1f, 0, 0}, {0, 1, 0.3f}, 1.0f), ~0u, 0, 1, 6));
    addBlob(b, {0.5f, 0.0f, 0.0f}, 0.15f, n, 0.0f);
    child->addTriangleMesh(b.triangles, std::vector<std::vector<Vec3f>>{b.vertices});
    top->addInstance(child, {Affine3f::translate({0.2f, 0.1f, 0.6f}) * Affine3f::scale(Vec3f(0.6f)),
                             Affine3f::translate({0.3f, 0.0f, 0.5f}) * Affine3f::scale(Vec3f(0.6f))},
                     {0.0f, 0.8f});
  }
  ProceduralScene ps;
  ps.name = "auto-test";
  ps.scene = top;
  ps.camera = frameBox(Box3f({-1.1f, -1.1f, -1.1f}, {1.1f, 1.1f, 1.1f}));
  return ps;
}

// A tube along x (rings x sides quads) bent at x = 0 by linear-blend
// skinning: the right half turns about the z axis by up to `bend` radians
// over `steps` vertex steps, the left stays, a band of width 0.3 around
// the joint blends the two; the whole drifts along y. Near-rigid: two
// clusters of coherent affine motion and a deforming joint (time range
// [0.05, 0.95], mask 1).
inline ProceduralScene bendingTubeScene(uint32_t rings = 48, uint32_t sides = 24, uint32_t steps = 6,
                                        float bend = 1.2f) {
  std::vector<Vec3f> rest;
  std::vector<Triangle> tris;
  for (uint32_t i = 0; i <= rings; ++i)
    for (uint32_t j = 0; j < sides; ++j) {
      const float x = -0.8f + 1.6f * float(i) / float(rings), a = 6.2831853f * float(j) / float(sides);
      rest.push_back({x, 0.15f * std::cos(a), 0.15f * std::sin(a)});
    }
  for (uint32_t i = 0; i < rings; ++i)
    for (uint32_t j = 0; j < sides; ++j) {
      const uint32_t a = i * sides + j, b = i * sides + (j + 1) % sides;
      tris.push_back({a, a + sides, b});
      tris.push_back({b, a + sides, b + sides});
    }
  std::vector<std::vector<Vec3f>> keys;
  for (uint32_t k = 0; k < steps; ++k) {
    const float f = float(k) / float(steps - 1);
    const Affine3f turn = Affine3f::rotate({0, 0, 1}, bend * f);
    const Vec3f drift{0.0f, 0.2f * f, 0.0f};
    std::vector<Vec3f> key;
    for (const Vec3f& v : rest) {
      const float s = std::clamp((v.x + 0.15f) / 0.3f, 0.0f, 1.0f), w = s * s * (3.0f - 2.0f * s);
      key.push_back(v * (1.0f - w) + turn.xfmPoint(v) * w + drift);
    }
    keys.push_back(std::move(key));
  }
  auto scene = std::make_shared<Scene>();
  scene->setMask(scene->addTriangleMesh(tris, keys, {0.05f, 0.95f}), 1u);
  ProceduralScene ps;
  ps.name = "bending-tube";
  ps.scene = scene;
  ps.camera = frameBox(Box3f({-1.0f, -1.0f, -1.0f}, {1.0f, 1.0f, 1.0f}));
  return ps;
}

}  // namespace mbrt::test
