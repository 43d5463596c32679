#include "auto/part_bounds.h"

#include <algorithm>

#include "scene/primitive_bounds.h"

namespace mbrt::detail {
namespace {

// Twice the residual (measured in double against the stored keys): the
// float evaluation of the keys and boxes adds a few ulp, which widen covers.
float residualMargin(const PartFit& fit) { return float(2.0 * fit.maxResidual * fit.diagonal); }

}  // namespace

std::vector<Box3f> partKeyBoxes(const Geometry& g, const RigidPart& part) {
  return trianglesKeyBoxes(g, part.prims, residualMargin(part.fit));
}

std::vector<Box3f> partKeyBoxes(const Geometry& g, std::span<const uint32_t> vertices, const PartFit& fit) {
  return verticesKeyBoxes(g, vertices, residualMargin(fit));
}

std::vector<Box3f> trianglesKeyBoxes(const Geometry& g, std::span<const uint32_t> prims, float margin) {
  std::vector<uint32_t> tris(prims.begin(), prims.end());
  if (tris.empty())
    for (uint32_t p = 0; p < g.numPrimitives(); ++p) tris.push_back(p);
  return verticesKeyBoxes(g, usedVertices(g, tris), margin);
}

std::vector<Box3f> verticesKeyBoxes(const Geometry& g, std::span<const uint32_t> vertices, float margin) {
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
