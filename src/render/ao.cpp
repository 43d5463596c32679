// `ao`: ambient occlusion, the MSBVH paper's renderer. At the primary hit,
// cosine-distributed occlusion rays of a fixed length, traced at the camera
// ray's time with occluded(); the albedo times the unoccluded fraction.
// Misses show the sky colour.
#include "render/integrator.h"
#include "render/surface.h"

namespace mbrt::renderer {

SampleResult traceAo(const Context& ctx, const Ray& ray, Sampler& sampler) {
  SampleResult out;
  out.rays = 1;
  Hit hit;
  if (!ctx.accel.intersect(ray, hit)) {
    out.color = ctx.scene.skyColor;
    return out;
  }
  const Surface s = surfaceAt(ctx.scene, ray, hit);
  const int n = std::max(1, ctx.options.aoSamples);
  int open = 0;
  for (int i = 0; i < n; ++i) {
    const float u1 = sampler.next(), u2 = sampler.next();
    const Ray shadow = s.spawn(cosineDirection(s.n, u1, u2), ray.time, ctx.epsilon, ctx.aoDistance);
    if (!ctx.accel.occluded(shadow)) ++open;
  }
  out.rays += uint32_t(n);
  out.color = s.albedo * (float(open) / float(n));
  return out;
}

}  // namespace mbrt::renderer
