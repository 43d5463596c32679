// sceneBounds (mbrt/scene.h): every vertex step (padded by its segment
// radius) and every instance key applied to the corners of its scene's box.
#include "mbrt/scene.h"

namespace mbrt {
namespace {

// Instance nesting deeper than this is refused by Scene::validate; the guard
// only keeps a cyclic scene from recursing forever here.
constexpr int kMaxDepth = 64;

Box3f boundsAtDepth(const Scene& scene, int depth) {
  Box3f box;
  if (depth > kMaxDepth) return box;
  for (uint32_t id = 0; id < scene.numGeometries(); ++id) {
    const Geometry& g = scene.geometry(id);
    if (g.type() == GeometryType::Instance) {
      const Box3f child = boundsAtDepth(*g.instancedScene(), depth + 1);
      if (child.empty()) continue;
      for (const Affine3f& m : g.transforms())
        for (int c = 0; c < 8; ++c)
          box.extend(m.xfmPoint({c & 1 ? child.upper.x : child.lower.x, c & 2 ? child.upper.y : child.lower.y,
                                 c & 4 ? child.upper.z : child.lower.z}));
      continue;
    }
    const auto radii = g.radii();
    for (uint32_t s = 0; s < g.numSteps(); ++s) {
      const VertexBuffer& vb = g.vertices(s);
      for (size_t i = 0; i < vb.count; ++i) {
        const Vec3f p = vb[i];
        const float r = i < radii.size() ? radii[i] : 0.0f;
        box.extend(p - Vec3f(r));
        box.extend(p + Vec3f(r));
      }
    }
  }
  return box;
}

}  // namespace

Box3f sceneBounds(const Scene& scene) { return boundsAtDepth(scene, 0); }

}  // namespace mbrt
