// `deform`: a 200k-triangle grid (size 1), 9 steps, a travelling wave (two
// sine waves, one planar and one circular, each advancing one wavelength
// over the shutter): non-rigid deformation.
#include <cmath>
#include <numbers>

#include "scenes/mesh_builders.h"
#include "scenes/scene_makers.h"

namespace mbrt::scenes {

ProceduralScene makeDeform(double size, uint64_t seed) {
  Rng rng(seed, 0x6465666f726dull);
  const int n = int(std::max<size_t>(2, scaledCount(std::sqrt(size), std::sqrt(100000.0), 2)));
  constexpr float kExtent = 4.0f;
  MeshData grid = makeGrid(n, n, kExtent, kExtent);

  constexpr float kTwoPi = 2.0f * std::numbers::pi_v<float>;
  const float heading = rng.uniform(0.0f, kTwoPi);
  const Vec3f dir{std::cos(heading), 0.0f, std::sin(heading)};
  const float wavelength = rng.uniform(1.2f, 1.8f);
  const Vec3f centre{rng.uniform(-1.0f, 1.0f), 0.0f, rng.uniform(-1.0f, 1.0f)};

  constexpr int kSteps = 9;
  std::vector<std::vector<Vec3f>> steps(kSteps, grid.vertices);
  for (int k = 0; k < kSteps; ++k) {
    const float phase = kTwoPi * float(k) / float(kSteps - 1);
    for (Vec3f& v : steps[k]) {
      const float planar = std::sin(kTwoPi * dot(v, dir) / wavelength - phase);
      const float r = length(v - centre);
      const float ripple = std::sin(kTwoPi * r / 0.7f - 2.0f * phase) * std::exp(-0.6f * r);
      v.y = 0.18f * planar + 0.08f * ripple;
    }
  }
  auto scene = std::make_shared<Scene>();
  scene->addTriangleMesh(std::move(grid.triangles), std::move(steps));
  ProceduralScene out;
  out.camera.eye = {3.3f, 2.6f, 3.9f};
  out.camera.target = {0.0f, -0.2f, 0.0f};
  out.camera.verticalFovDegrees = 40.0f;
  out.scene = std::move(scene);
  return out;
}

}  // namespace mbrt::scenes
