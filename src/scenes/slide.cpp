// `slide`: the simplest motion a renderer meets, one rigid object sliding:
// a bumpy blob of 20k triangles (size 1) with 2 time steps, moved in a
// straight line by twice its radius over the shutter.
#include "scenes/mesh_builders.h"
#include "scenes/scene_makers.h"

namespace mbrt::scenes {

ProceduralScene makeSlide(double size, uint64_t seed) {
  Rng rng(seed, 0x736c696465000000ull);
  BlobShape shape;
  shape.base = 0.85f;
  shape.addRandomLobes(rng, 6, 0.08f, 0.16f, 3.0f, 8.0f);    // broad swellings
  shape.addRandomLobes(rng, 20, 0.02f, 0.05f, 20.0f, 50.0f);  // small bumps
  MeshData mesh = makeSphere(scaledCount(size, 20000, 16), shape);

  float radius = 0.0f;
  for (const Vec3f& v : mesh.vertices) radius = std::max(radius, length(v));
  const Vec3f dir = normalize(Vec3f{1.0f, 0.2f, -0.3f} + rng.inUnitBall() * 0.2f);
  std::vector<std::vector<Vec3f>> steps{transformed(mesh.vertices, Affine3f::translate(dir * -radius)),
                                        transformed(mesh.vertices, Affine3f::translate(dir * radius))};
  auto scene = std::make_shared<Scene>();
  scene->addTriangleMesh(std::move(mesh.triangles), std::move(steps));
  ProceduralScene out;
  out.camera = viewFrom(sceneBounds(*scene), {0.55f, 0.45f, 1.0f}, 40.0f, 0.9f);
  out.scene = std::move(scene);
  return out;
}

}  // namespace mbrt::scenes
