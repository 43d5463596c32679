#include "auto/part_bounds.h"

#include <algorithm>

#include "scene/primitive_bounds.h"

namespace mbrt::detail {

std::vector<Box3f> partKeyBoxes(const Geometry& g, const RigidPart& part) {
  // Twice the residual (measured in double against the stored keys): the
  // float evaluation of the keys and boxes adds a few ulp, which widen covers.
  return trianglesKeyBoxes(g, part.prims, float(2.0 * part.fit.maxResidual * part.fit.diagonal));
}

std::vector<Box3f> trianglesKeyBoxes(const Geometry& g, std::span<const uint32_t> prims, float margin) {
  std::vector<uint32_t> tris(prims.begin(), prims.end());
  if (tris.empty())
    for (uint32_t p = 0; p < g.numPrimitives(); ++p) tris.push_back(p);
  const std::vector<uint32_t> vertices = usedVertices(g, tris);
  std::vector<Box3f> boxes(g.numSteps());
  for (uint32_t k = 0; k < g.numSteps(); ++k) {
    Box3f b;
    for (uint32_t v : vertices) b.extend(g.vertices(k)[v]);
    b.lower = b.lower - Vec3f(margin);
    b.upper = b.upper + Vec3f(margin);
    boxes[k] = widen(b);
  }
  return boxes;
}

}  // namespace mbrt::detail
