// `translate`: one bumpy blob (200k triangles at size 1), 6 steps, moving in a
// straight line over twice its radius.
#include "scenes/mesh_builders.h"
#include "scenes/scene_makers.h"

namespace mbrt::scenes {

ProceduralScene makeTranslate(double size, uint64_t seed) {
  Rng rng(seed, 0x7472616e736c6174ull);
  BlobShape shape;
  shape.base = 0.85f;
  shape.addRandomLobes(rng, 6, 0.08f, 0.16f, 3.0f, 8.0f);    // broad swellings
  shape.addRandomLobes(rng, 40, 0.02f, 0.05f, 30.0f, 80.0f);  // small bumps
  MeshData mesh = makeSphere(scaledCount(size, 200000, 16), shape);

  float radius = 0.0f;
  for (const Vec3f& v : mesh.vertices) radius = std::max(radius, length(v));
  // A mostly horizontal direction that varies a little with the seed.
  const Vec3f dir = normalize(Vec3f{1.0f, 0.25f, -0.35f} + rng.inUnitBall() * 0.2f);

  constexpr int kSteps = 6;
  std::vector<std::vector<Vec3f>> steps;
  for (int k = 0; k < kSteps; ++k) {
    const float s = -radius + 2.0f * radius * float(k) / float(kSteps - 1);
    steps.push_back(transformed(mesh.vertices, Affine3f::translate(dir * s)));
  }
  auto scene = std::make_shared<Scene>();
  scene->addTriangleMesh(std::move(mesh.triangles), std::move(steps));
  ProceduralScene out;
  out.camera = viewFrom(sceneBounds(*scene), {0.55f, 0.45f, 1.0f}, 40.0f, 0.9f);
  out.scene = std::move(scene);
  return out;
}

}  // namespace mbrt::scenes
