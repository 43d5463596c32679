// `heat-steps` / `heat-isects`: the work of a primary ray from the counted
// intersect (nodes visited, or ray-primitive tests). The colour map and its
// bar are applied to the whole image afterwards (colormap.h).
#include "render/integrator.h"

namespace mbrt::renderer {

SampleResult traceHeat(const Context& ctx, const Ray& ray, Sampler&) {
  SampleResult out;
  out.rays = 1;
  TraversalCounters counters;
  Hit hit;
  ctx.accel.intersect(ray, hit, counters);
  out.value = float(ctx.options.integrator == IntegratorKind::HeatSteps ? counters.nodesVisited
                                                                        : counters.primitiveTests);
  return out;
}

}  // namespace mbrt::renderer
