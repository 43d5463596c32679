// What every integrator sees, and the one entry point per integrator (one
// file each: normals.cpp, ao.cpp, path.cpp, heat.cpp, clusters.cpp).
#pragma once

#include <cstdint>
#include <vector>

#include "mbrt/render.h"
#include "render/sampler.h"

namespace mbrt::renderer {

struct Context {
  const SceneDescription& scene;
  const Accel& accel;
  const RenderOptions& options;
  float aoDistance = 1.0f;  // occlusion ray length
  float epsilon = 1e-4f;    // ray offset off surfaces, scaled to the scene
};

// What one camera sample returns: a colour, or for heat maps a work count
// in `value`.
struct SampleResult {
  Vec3f color;
  float value = 0.0f;
  uint32_t rays = 0;  // rays traced for this sample
};

SampleResult traceNormals(const Context& ctx, const Ray& ray, Sampler& sampler);
SampleResult traceAo(const Context& ctx, const Ray& ray, Sampler& sampler);
SampleResult tracePath(const Context& ctx, const Ray& ray, Sampler& sampler);
SampleResult traceHeat(const Context& ctx, const Ray& ray, Sampler& sampler);
SampleResult traceClusters(const Context& ctx, const Ray& ray, Sampler& sampler);
Vec3f clusterColor(uint32_t cluster);

}  // namespace mbrt::renderer
