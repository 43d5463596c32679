// `clusters`: the paper's Fig. 1 — every triangle coloured by the motion
// cluster (decompose/) whose fuzzy kd-tree holds it, shaded by the facing
// ratio so the shape stays readable; triangles in fuzzykd's world-space tree
// (static or small meshes, clusters that fell back) are grey. Over `auto`
// the groups are its objects (extracted instances, the remaining meshes;
// docs/auto.md), through the same Accel::clusterOf.
#include <cmath>

#include "render/integrator.h"
#include "render/surface.h"

namespace mbrt::renderer {

// A well-spread hue per cluster (golden-ratio steps around the hue circle).
Vec3f clusterColor(uint32_t cluster) {
  const float h = std::fmod(0.13f + 0.6180339887f * float(cluster), 1.0f) * 6.0f;
  const float s = cluster % 2 ? 0.55f : 0.8f, v = cluster % 3 == 1 ? 0.75f : 0.95f;
  const int i = int(h);
  const float f = h - float(i), p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
  switch (i % 6) {
    case 0: return {v, t, p};
    case 1: return {q, v, p};
    case 2: return {p, v, t};
    case 3: return {p, q, v};
    case 4: return {t, p, v};
    default: return {v, p, q};
  }
}

SampleResult traceClusters(const Context& ctx, const Ray& ray, Sampler&) {
  SampleResult out;
  out.rays = 1;
  Hit hit;
  if (!ctx.accel.intersect(ray, hit)) return out;  // black background
  const Surface s = surfaceAt(ctx.scene, ray, hit);
  uint32_t cluster = ~0u;
  if (hit.instID == kInvalidId) cluster = ctx.accel.clusterOf(hit.geomID, hit.primID);
  const Vec3f base = cluster == ~0u ? Vec3f(0.5f) : clusterColor(cluster);
  const float facing = std::abs(dot(s.n, normalize(ray.dir)));
  out.color = base * (0.25f + 0.75f * facing);
  return out;
}

}  // namespace mbrt::renderer
