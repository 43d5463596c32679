#include "auto/ray_cost.h"

#include <algorithm>
#include <cmath>

namespace mbrt::detail {
namespace {

// xorshift64*: a fixed, portable sequence.
struct SampleRng {
  uint64_t state = 0x9E3779B97F4A7C15ull;
  float next() {
    state ^= state >> 12;
    state ^= state << 25;
    state ^= state >> 27;
    return float((state * 2685821657736338717ull) >> 40) * (1.0f / 16777216.0f);
  }
};

}  // namespace

RayCostWeights weightsFor(const Scene& scene) {
  RayCostWeights w;
  double triangles = 0, segments = 0;
  for (uint32_t id = 0; id < scene.numGeometries(); ++id) {
    const Geometry& g = scene.geometry(id);
    if (g.type() == GeometryType::Triangles) triangles += g.numPrimitives();
    if (g.type() == GeometryType::Segments) segments += g.numPrimitives();
  }
  if (segments > 0) w.primitive = (triangles + w.segment * segments) / (triangles + segments);
  return w;
}

std::vector<RayQuery> sampleRays(const SceneContext& context) {
  std::vector<RayQuery> rays;
  const Box3f box = sceneBounds(context.scene());
  if (!(box.lower.x <= box.upper.x && box.lower.y <= box.upper.y && box.lower.z <= box.upper.z)) return rays;
  const Vec3f centre = (box.lower + box.upper) * 0.5f, extent = box.upper - box.lower;
  const float radius = std::max(0.5f * length(extent), 1e-6f) * 1.5f;
  SampleRng rng;
  rays.reserve(kSampleRays / 2);
  // Bounded: a scene near the largest coordinates may refuse most rays.
  for (uint32_t tries = 0; rays.size() < kSampleRays / 2 && tries < 8 * kSampleRays; ++tries) {
    // A direction uniform on the sphere, the origin on it, the target inside the box.
    const float z = 2.0f * rng.next() - 1.0f, phi = 6.2831853f * rng.next();
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    const Vec3f org = centre + Vec3f{r * std::cos(phi), r * std::sin(phi), z} * radius;
    const Vec3f target{box.lower.x + extent.x * rng.next(), box.lower.y + extent.y * rng.next(),
                       box.lower.z + extent.z * rng.next()};
    const Vec3f dir = target - org;
    const float time = rng.next();
    if (!(length(dir) > 0.0f)) continue;
    Ray ray;
    ray.org = org;
    ray.dir = dir;
    ray.time = time;
    if (!isValidRay(ray)) continue;
    rays.emplace_back(ray);
  }
  return rays;
}

std::vector<RayQuery> bounceRays(const std::vector<RayQuery>& rays, const std::vector<Hit>& hits) {
  struct SurfacePoint {
    Vec3f p, n;
    float time, eps;
  };
  std::vector<SurfacePoint> points;
  for (size_t i = 0; i < rays.size() && i < hits.size(); ++i) {
    const RayQuery& r = rays[i];
    const Hit& h = hits[i];
    // The normal scaled to its largest component first: the cross product of
    // huge edges (coordinates near kMaxCoordinate) overflows its length.
    const Vec3f a{std::fabs(h.Ng.x), std::fabs(h.Ng.y), std::fabs(h.Ng.z)};
    const float largest = maxComponent(a);
    if (!h.valid() || !(largest > 0.0f) || !std::isfinite(largest)) continue;
    Vec3f n = normalize(h.Ng * (1.0f / largest));
    if (!(length(n) > 0.5f)) continue;
    if (dot(n, r.dir) > 0.0f) n = -n;
    points.push_back({r.org + r.dir * h.t, n, r.time, 1e-4f * length(r.dir)});
  }
  std::vector<RayQuery> out;
  if (points.empty()) return out;
  SampleRng rng;
  rng.state ^= 0xB5AD4ECEDA1CE2A9ull;
  out.reserve(rays.size());
  for (size_t j = 0; j < rays.size(); ++j) {
    const SurfacePoint& h = points[j % points.size()];
    const float u1 = rng.next(), u2 = rng.next();
    const float r = std::sqrt(u1), phi = 6.2831853f * u2;
    const Vec3f a = std::fabs(h.n.x) > 0.9f ? Vec3f(0, 1, 0) : Vec3f(1, 0, 0);
    const Vec3f t1 = normalize(cross(a, h.n)), t2 = cross(h.n, t1);
    const Vec3f dir = t1 * (r * std::cos(phi)) + t2 * (r * std::sin(phi)) + h.n * std::sqrt(std::max(0.0f, 1.0f - u1));
    Ray ray;
    ray.org = h.p + h.n * h.eps;
    ray.dir = dir;
    ray.tnear = h.eps;
    ray.time = h.time;
    if (!isValidRay(ray)) continue;  // what the API refuses is not traced here either
    out.emplace_back(ray);
  }
  return out;
}

RayCost measureRayCost(const Structure& s, const std::vector<RayQuery>& rays, const EntryTally* tally) {
  RayCost cost;
  if (rays.empty()) return cost;
  TraversalCounters counters;
  const EntryTally::Counts before = tally ? tally->read() : EntryTally::Counts{};
  std::vector<Hit> hits(rays.size());
  for (size_t i = 0; i < rays.size(); ++i) {
    RayQuery q = rays[i];
    s.intersectCounted(q, hits[i], counters);
  }
  const std::vector<RayQuery> bounces = bounceRays(rays, hits);
  for (const RayQuery& b : bounces) {
    RayQuery q = b;
    Hit hit;
    s.intersectCounted(q, hit, counters);
  }
  const double n = double(rays.size() + bounces.size());
  cost.nodes = double(counters.nodesVisited) / n;
  cost.primitives = double(counters.primitiveTests) / n;
  cost.blockPrimitives = double(counters.blockPrimitiveTests) / n;
  const EntryTally::Counts after = tally ? tally->read() : EntryTally::Counts{};
  cost.entries = (after.entries - before.entries) / n;
  cost.frozenNodes = (after.frozenNodes - before.frozenNodes) / n;
  cost.frozenPrimitives = (after.frozenPrimitives - before.frozenPrimitives) / n;
  cost.frozenBlockPrimitives = (after.frozenBlockPrimitives - before.frozenBlockPrimitives) / n;
  return cost;
}

}  // namespace mbrt::detail
