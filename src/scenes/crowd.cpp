// `crowd`: 100 objects of ~4k triangles (size 1) standing on a 10x10 ground
// area, plus a 50k-triangle hero in the middle. Objects have 2, 6 or 15 steps
// (exactly 60/30/10 of them) and translate and turn a little; the hero has 33
// steps and makes one full turn. One object exists only in [0.25, 1].
#include <cmath>
#include <numbers>

#include "scenes/mesh_builders.h"
#include "scenes/scene_makers.h"

namespace mbrt::scenes {
namespace {

constexpr float kTwoPi = 2.0f * std::numbers::pi_v<float>;
constexpr int kObjects = 100;
constexpr int kGrid = 11;          // candidate cells per side
constexpr float kHalfExtent = 5.0f;

// One of five shapes, about `tris` triangles, roughly unit size, centred.
MeshData makeShape(uint32_t kind, size_t tris, Rng& rng) {
  switch (kind) {
    case 0: {  // lumpy blob
      BlobShape s;
      s.base = 0.8f;
      s.addRandomLobes(rng, 5, 0.1f, 0.3f, 4.0f, 12.0f);
      return makeSphere(tris, s);
    }
    case 1: {  // rounded cube (superellipsoid)
      const float p = rng.uniform(3.0f, 6.0f);
      return makeSphere(tris, [p](Vec3f d) {
        const float q = std::pow(std::fabs(d.x), p) + std::pow(std::fabs(d.y), p) + std::pow(std::fabs(d.z), p);
        return 0.8f / std::pow(q, 1.0f / p);
      });
    }
    case 2: {  // pillar
      const float h = rng.uniform(1.2f, 2.0f);
      return makeCylinder(tris, {0, -0.5f * h, 0}, {0, 0.5f * h, 0}, 0.45f, rng.uniform(0.25f, 0.5f));
    }
    case 3: {  // cone
      return makeCylinder(tris, {0, -0.6f, 0}, {0, 0.9f, 0}, 0.7f, 0.02f);
    }
    default: {  // standing torus
      MeshData m = makeTorus(tris, 0.6f, rng.uniform(0.15f, 0.3f));
      transformInPlace(m.vertices, Affine3f::rotate({1, 0, 0}, 0.5f * std::numbers::pi_v<float>));
      return m;
    }
  }
}

}  // namespace

ProceduralScene makeCrowd(double size, uint64_t seed) {
  auto scene = std::make_shared<Scene>();
  Rng rng(seed, 0x63726f7764ull);

  // Ground cells, leaving the middle free for the hero.
  std::vector<Vec3f> cells;
  const float cell = 2.0f * kHalfExtent / kGrid;
  for (int j = 0; j < kGrid; ++j)
    for (int i = 0; i < kGrid; ++i) {
      const Vec3f c{-kHalfExtent + cell * (float(i) + 0.5f), 0.0f, -kHalfExtent + cell * (float(j) + 0.5f)};
      if (length(c) > 1.6f) cells.push_back(c);
    }
  rng.shuffle(cells);
  // Step counts: exactly 60 % with 2, 30 % with 6, 10 % with 15.
  std::vector<uint32_t> stepCounts;
  for (int i = 0; i < kObjects; ++i) stepCounts.push_back(i < 60 ? 2u : (i < 90 ? 6u : 15u));
  rng.shuffle(stepCounts);

  const size_t objectTris = scaledCount(size, 4000, 16);
  bool partialDone = false;
  for (int o = 0; o < kObjects; ++o) {
    Rng orng(seed, 0x6f626a00ull + uint64_t(o));
    const uint32_t kind = orng.below(5);
    MeshData m = makeShape(kind, objectTris, orng);
    const float scale = orng.uniform(0.28f, 0.42f);
    transformInPlace(m.vertices, Affine3f::scale(Vec3f(scale)));
    const Box3f b = boundsOf(m.vertices);
    transformInPlace(m.vertices, Affine3f::translate({-b.center().x, -b.lower.y, -b.center().z}));  // stand on y = 0

    const Vec3f jitter{orng.uniform(-0.15f, 0.15f), 0.0f, orng.uniform(-0.15f, 0.15f)};
    const Vec3f start = cells[o] + jitter * cell;
    const float heading = orng.uniform(0.0f, kTwoPi);
    const float distance = orng.uniform(0.1f, 0.45f);
    const Vec3f delta{std::cos(heading) * distance, 0.0f, std::sin(heading) * distance};
    const float yaw0 = orng.uniform(0.0f, kTwoPi);
    const float turn = orng.uniform(-0.6f, 0.6f);
    const float hop = orng.uniform(0.0f, 0.15f);

    const uint32_t S = stepCounts[o];
    std::vector<std::vector<Vec3f>> steps;
    for (uint32_t k = 0; k < S; ++k) {
      const float f = float(k) / float(S - 1);
      const Vec3f pos = start + delta * f + Vec3f{0.0f, hop * std::sin(std::numbers::pi_v<float> * f), 0.0f};
      steps.push_back(transformed(m.vertices, Affine3f::translate(pos) * Affine3f::rotate({0, 1, 0}, yaw0 + turn * f)));
    }
    TimeRange range;
    if (!partialDone && S == 6) {  // one object appears a quarter into the shutter
      range = {0.25f, 1.0f};
      partialDone = true;
    }
    scene->addTriangleMesh(std::move(m.triangles), std::move(steps), range);
  }

  // The hero: a big blob with arms, one full turn about a slightly tilted axis.
  BlobShape hero;
  hero.base = 0.55f;
  hero.addRandomLobes(rng, 6, 0.3f, 0.6f, 8.0f, 20.0f);
  hero.addRandomLobes(rng, 20, 0.02f, 0.05f, 30.0f, 60.0f);
  MeshData h = makeSphere(scaledCount(size, 50000, 16), hero);
  const Vec3f heroCentre{0.0f, 1.4f, 0.0f};
  const Vec3f axis = normalize(Vec3f{0.15f, 1.0f, -0.1f});
  constexpr uint32_t kHeroSteps = 33;
  std::vector<std::vector<Vec3f>> heroSteps;
  for (uint32_t k = 0; k < kHeroSteps; ++k) {
    const float angle = kTwoPi * float(k) / float(kHeroSteps - 1);
    heroSteps.push_back(transformed(h.vertices, Affine3f::translate(heroCentre) * Affine3f::rotate(axis, angle)));
  }
  scene->addTriangleMesh(std::move(h.triangles), std::move(heroSteps));

  ProceduralScene out;
  out.camera.eye = {5.5f, 5.0f, 8.5f};
  out.camera.target = {0.0f, 0.9f, 0.0f};
  out.camera.verticalFovDegrees = 45.0f;
  out.scene = std::move(scene);
  return out;
}

}  // namespace mbrt::scenes
