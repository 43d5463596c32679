// `normals`: primary visibility, the geometric normal mapped to colour.
#include "render/integrator.h"
#include "render/surface.h"

namespace mbrt::renderer {

SampleResult traceNormals(const Context& ctx, const Ray& ray, Sampler&) {
  SampleResult out;
  out.rays = 1;
  Hit hit;
  if (!ctx.accel.intersect(ray, hit)) return out;  // black background
  const Surface s = surfaceAt(ctx.scene, ray, hit);
  out.color = (s.n + Vec3f(1.0f)) * 0.5f;
  return out;
}

}  // namespace mbrt::renderer
