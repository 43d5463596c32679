// The incoherent ray set: rays from all around a scene into it, each aimed
// at a point of one of its primitives at the ray's time, so that nearly all
// of them hit and consecutive rays share no path (what a path tracer's
// later bounces look like to the kernel). It depends on the scene alone,
// not on a camera or a structure, so every kind and Embree trace the very
// same rays.
#include <cmath>
#include <numbers>
#include <optional>

#include "mbrt/bench.h"
#include "bench/bench_internal.h"

namespace mbrt::bench {
namespace {

struct Draw {
  uint64_t seed, index;
  uint64_t stream = 8;  // streams 0-7: the ray's own numbers
  float next() { return uniform(seed, index, stream++); }
};

// A point on a primitive of `scene` drawn uniformly among its primitives,
// at `time` (moved inside the drawn geometry's time range; an instanced
// scene is sampled at the instance's time), or false when the scene has
// nothing to draw.
bool surfacePoint(const Scene& scene, float& time, Draw& d, Vec3f& out, int depth = 0) {
  const size_t total = scene.numPrimitives();
  if (total == 0 || depth > 8) return false;
  size_t k = std::min(total - 1, size_t(double(d.next()) * double(total)));
  uint32_t id = 0;
  while (k >= scene.geometry(id).numPrimitives()) k -= scene.geometry(id).numPrimitives(), ++id;
  const Geometry& g = scene.geometry(id);
  const TimeRange r = g.timeRange();
  time = std::clamp(time, r.lo, r.hi);
  const uint32_t prim = uint32_t(k);
  switch (g.type()) {
    case GeometryType::Triangles: {
      const Triangle& t = g.triangles()[prim];
      float a = d.next(), b = d.next();
      if (a + b > 1.0f) a = 1.0f - a, b = 1.0f - b;
      const Vec3f p0 = g.vertexAt(time, t.v0), p1 = g.vertexAt(time, t.v1), p2 = g.vertexAt(time, t.v2);
      out = p0 + (p1 - p0) * a + (p2 - p0) * b;
      return true;
    }
    case GeometryType::Segments: {
      const Segment& s = g.segments()[prim];
      const float a = d.next();
      out = lerp(g.vertexAt(time, s.v0), g.vertexAt(time, s.v1), a);
      return true;
    }
    case GeometryType::Instance: {
      Vec3f local;
      float childTime = time;
      if (!surfacePoint(*g.instancedScene(), childTime, d, local, depth + 1)) return false;
      out = g.transformAt(time).xfmPoint(local);
      return true;
    }
  }
  return false;
}

}  // namespace

std::vector<Ray> incoherentRays(const Scene& scene, size_t n, uint64_t seed, std::optional<float> time) {
  std::vector<Ray> rays;
  rays.reserve(n);
  const Box3f box = sceneBounds(scene);
  const float radius = length(box.upper - box.lower);
  if (!(radius > 0.0f) || !std::isfinite(radius)) return rays;
  for (size_t j = 0; rays.size() < n && j < 4 * n; ++j) {
    Draw d{seed, j};
    float t = time ? *time : uniform(seed, j, 0);
    Vec3f target;
    if (!surfacePoint(scene, t, d, target) || (time && t != *time)) continue;  // with `time`: alive then
    const float z = 1.0f - 2.0f * uniform(seed, j, 1), phi = 2.0f * std::numbers::pi_v<float> * uniform(seed, j, 2);
    const float s = std::sqrt(std::max(0.0f, 1.0f - z * z));
    const Vec3f w{s * std::cos(phi), s * std::sin(phi), z};
    Ray r;
    r.org = target + w * radius;
    r.dir = -w;
    r.time = t;
    rays.push_back(r);
  }
  return rays;
}

}  // namespace mbrt::bench
