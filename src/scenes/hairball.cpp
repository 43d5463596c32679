// `hairball`: 300k triangles (size 1) as thin ribbons along 10k random
// strands in the unit ball, 3 steps; every strand moves its own way by ~5 %
// of the scene's size along a bent path. `ribbons`: the same ball at 20k
// triangles with 2 steps, each strand moving in a straight line (the
// simplest motion of many small independent pieces).
#include "scenes/mesh_builders.h"
#include "scenes/scene_makers.h"
#include "scenes/strands.h"

namespace mbrt::scenes {
namespace {

// `triangles` (at size 1) in ribbons of 30 triangles, with `steps` (2 or 3)
// time steps: step k at strandMotion's offset k, 2 steps ending at its last.
ProceduralScene ribbonBall(double size, uint64_t seed, double triangles, int steps) {
  constexpr int kPoints = 16;  // 30 triangles per strand
  const size_t strands = scaledCount(size, triangles / (2 * (kPoints - 1)), 1);
  constexpr float kBall = 1.0f;
  constexpr float kWidth = 0.005f;
  constexpr float kMove = 0.05f * 2.0f * kBall;  // 5 % of the scene's diameter

  MeshData mesh;
  mesh.vertices.reserve(strands * 2 * kPoints);
  mesh.triangles.reserve(strands * 2 * (kPoints - 1));
  std::vector<std::vector<Vec3f>> stepVertices(static_cast<size_t>(steps));
  for (auto& s : stepVertices) s.reserve(strands * 2 * kPoints);
  for (size_t i = 0; i < strands; ++i) {
    const std::vector<Vec3f> pts = wanderingStrand(seed, 0x68620000000ull + i, kPoints, 0.045f, kBall);
    Rng rng(seed, 0x686e0000000ull + i);
    const size_t first = mesh.vertices.size();
    appendRibbon(mesh, pts, rng.unitVector(), kWidth);
    const StrandMotion motion = strandMotion(seed, 0x686d0000000ull + i, kMove, 0.35f);
    for (int k = 0; k < steps; ++k) {
      const Vec3f offset = motion.offset[steps == 2 ? 2 * k : k];
      for (size_t v = first; v < mesh.vertices.size(); ++v) stepVertices[size_t(k)].push_back(mesh.vertices[v] + offset);
    }
  }
  auto scene = std::make_shared<Scene>();
  scene->addTriangleMesh(std::move(mesh.triangles), std::move(stepVertices));
  ProceduralScene out;
  out.camera = viewFrom(sceneBounds(*scene), {0.5f, 0.4f, 1.0f}, 40.0f, 0.75f);
  out.scene = std::move(scene);
  return out;
}

}  // namespace

ProceduralScene makeHairball(double size, uint64_t seed) { return ribbonBall(size, seed, 300000.0, 3); }
ProceduralScene makeRibbons(double size, uint64_t seed) { return ribbonBall(size, seed, 20000.0, 2); }

}  // namespace mbrt::scenes
