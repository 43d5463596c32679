#include "render/scene_bounds.h"

namespace mbrt::renderer {
namespace {

Box3f boundsRec(const Scene& scene, int depth) {
  Box3f box;
  if (depth > 16) return box;
  for (uint32_t g = 0; g < scene.numGeometries(); ++g) {
    const Geometry& geom = scene.geometry(g);
    if (geom.type() == GeometryType::Instance) {
      const Box3f child = boundsRec(*geom.instancedScene(), depth + 1);
      if (child.empty()) continue;
      for (const Affine3f& xfm : geom.transforms())
        for (int c = 0; c < 8; ++c) {
          const Vec3f corner{(c & 1) ? child.upper.x : child.lower.x, (c & 2) ? child.upper.y : child.lower.y,
                             (c & 4) ? child.upper.z : child.lower.z};
          box.extend(xfm.xfmPoint(corner));
        }
      continue;
    }
    float radius = 0.0f;
    for (float r : geom.radii()) radius = std::max(radius, r);
    for (uint32_t s = 0; s < geom.numSteps(); ++s) {
      const VertexBuffer& vb = geom.vertices(s);
      for (size_t i = 0; i < vb.count; ++i) {
        const Vec3f p = vb[i];
        box.extend(Box3f(p - Vec3f(radius), p + Vec3f(radius)));
      }
    }
  }
  return box;
}

}  // namespace

Box3f sceneBounds(const Scene& scene) { return boundsRec(scene, 0); }

}  // namespace mbrt::renderer
