// `rotate`: one non-symmetric blob with arms (200k triangles at size 1),
// 33 steps, two full turns about an off-centre, slightly tilted axis. Every
// step's vertices are rotated exactly (the curve is sampled, not linearized).
#include <numbers>

#include "scenes/mesh_builders.h"
#include "scenes/scene_makers.h"

namespace mbrt::scenes {

ProceduralScene makeRotate(double size, uint64_t seed) {
  Rng rng(seed, 0x726f74617465ull);
  BlobShape shape;
  shape.base = 0.45f;
  shape.addRandomLobes(rng, 5, 0.35f, 0.75f, 10.0f, 25.0f);  // arms of different lengths
  shape.addRandomLobes(rng, 3, 0.10f, 0.20f, 3.0f, 6.0f);    // an uneven body
  shape.addRandomLobes(rng, 24, 0.02f, 0.04f, 30.0f, 60.0f);
  MeshData mesh = makeSphere(scaledCount(size, 200000, 16), shape);

  const Vec3f axis = normalize(Vec3f{0.25f, 1.0f, 0.15f});
  const Vec3f pivot{0.7f, 0.0f, 0.25f};  // the mesh orbits around this line
  constexpr int kSteps = 33;
  constexpr float kTurns = 2.0f;
  std::vector<std::vector<Vec3f>> steps;
  for (int k = 0; k < kSteps; ++k) {
    const float angle = kTurns * 2.0f * std::numbers::pi_v<float> * float(k) / float(kSteps - 1);
    steps.push_back(transformed(mesh.vertices, rotateAbout(pivot, axis, angle)));
  }
  auto scene = std::make_shared<Scene>();
  scene->addTriangleMesh(std::move(mesh.triangles), std::move(steps));
  ProceduralScene out;
  out.camera = viewFrom(sceneBounds(*scene), {0.6f, 0.7f, 1.0f}, 40.0f, 0.85f);
  out.scene = std::move(scene);
  return out;
}

}  // namespace mbrt::scenes
