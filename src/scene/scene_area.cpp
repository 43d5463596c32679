#include "scene/scene_area.h"

#include "scene/primitive_bounds.h"

namespace mbrt::detail {

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
