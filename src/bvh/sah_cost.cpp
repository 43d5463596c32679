#include "bvh/sah_cost.h"

#include "geometry/primitive_bounds.h"

namespace mbrt::detail {

double meanSurfaceArea(const LBounds& b, float lo, float hi) {
  double sum = 0.0;
  for (int k = 0; k < 8; ++k) sum += double(b.at(lo + (hi - lo) * float(k) / 7.0f).area());
  return sum / 8.0;
}

double sceneSahArea(const SceneContext& ctx) {
  Box3f box;
  for (const PrimRef& p : ctx.primitives()) {
    const LBounds b = linearBounds(ctx, p, {0.0f, 1.0f});
    if (isFinite(b.b0.lower) && isFinite(b.b0.upper) && isFinite(b.b1.lower) && isFinite(b.b1.upper))
      box.extend(b.hull());
  }
  return double(box.area());
}

}  // namespace mbrt::detail
