// `path`: diffuse path tracing, the STBVH paper's renderer. Lambertian
// surfaces lit by the directional lights (next-event estimation with shadow
// rays; a light's `radiance` is its irradiance on a surface facing it) and a
// uniform sky, cosine-sampled bounces, Russian roulette after two bounces.
// Every ray of a path keeps the camera ray's time.
#include <numbers>

#include "render/integrator.h"
#include "render/surface.h"

namespace mbrt::renderer {

SampleResult tracePath(const Context& ctx, const Ray& cameraRay, Sampler& sampler) {
  SampleResult out;
  Vec3f radiance, throughput(1.0f);
  Ray ray = cameraRay;
  constexpr float kInvPi = 1.0f / std::numbers::pi_v<float>;
  for (int depth = 0;; ++depth) {
    Hit hit;
    ++out.rays;
    if (!ctx.accel.intersect(ray, hit)) {
      radiance += throughput * ctx.scene.skyColor;
      break;
    }
    const Surface s = surfaceAt(ctx.scene, ray, hit);
    for (const DirectionalLight& light : ctx.scene.lights) {
      const float len = length(light.direction);
      if (!(len > 0.0f)) continue;
      const Vec3f toLight = light.direction * (-1.0f / len);
      const float cosTheta = dot(s.n, toLight);
      if (cosTheta <= 0.0f) continue;
      ++out.rays;
      if (ctx.accel.occluded(s.spawn(toLight, ray.time, ctx.epsilon))) continue;
      radiance += throughput * s.albedo * light.radiance * (cosTheta * kInvPi);
    }
    if (depth >= ctx.options.maxDepth) break;
    // Cosine sampling: the pdf cancels the cosine and 1/pi of the BRDF.
    throughput = throughput * s.albedo;
    if (depth >= 2) {
      const float q = std::min(0.95f, maxComponent(throughput));
      if (sampler.next() >= q) break;
      throughput *= 1.0f / q;
    }
    const float u1 = sampler.next(), u2 = sampler.next();
    ray = s.spawn(cosineDirection(s.n, u1, u2), ray.time, ctx.epsilon);
  }
  out.color = radiance;
  return out;
}

}  // namespace mbrt::renderer
