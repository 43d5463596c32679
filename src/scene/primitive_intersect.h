// The one leaf test every structure (and the brute-force oracle) uses: a
// primitive at the ray's time, with geometry masks, time ranges,
// intersection filters and instances. Structures differ only in which
// primitives they test, never in how.
#pragma once

#include "scene/instance_space.h"
#include "scene/scene_context.h"
#include "geometry/segment_intersect.h"
#include "geometry/triangle_intersect.h"

namespace mbrt::detail {

namespace leaf_detail {

inline bool accept(const Geometry& g, const RayQuery& ray, const Hit& candidate) {
  if (!g.hasFilter()) return true;
  const Ray r = ray.toRay();
  return g.filter()(FilterArgs{r, candidate, g.userData()});
}

// The hit of segment `ref` that the segment test found.
inline Hit segmentHit(PrimRef ref, const SegmentHit& sh) {
  Hit h;
  h.t = sh.t;
  h.u = sh.u;
  h.v = 0.0f;
  h.Ng = sh.Ng;
  h.geomID = ref.geomID;
  h.primID = ref.primID;
  h.instID = kInvalidId;
  return h;
}

// Candidate hit of a triangle or segment (not instances); false on a miss.
inline bool candidate(const Geometry& g, PrimRef ref, const RayQuery& ray, Hit& out) {
  uint32_t s;
  float f;
  g.segmentAt(ray.time, s, f);
  const bool moving = g.numSteps() > 1;
  auto vertex = [&](uint32_t i) {
    return moving ? lerp(g.vertices(s)[i], g.vertices(s + 1)[i], f) : g.vertices(0)[i];
  };
  if (g.type() == GeometryType::Triangles) {
    const Triangle& tri = g.triangles()[ref.primID];
    const Vec3f v0 = vertex(tri.v0), v1 = vertex(tri.v1), v2 = vertex(tri.v2);
    TriangleHit th;
    if (!intersectTriangle(ray, v0, v1, v2, th)) return false;
    out.t = th.t;
    out.u = th.u;
    out.v = th.v;
    out.Ng = cross(v1 - v0, v2 - v0);
  } else {
    const Segment& seg = g.segments()[ref.primID];
    SegmentHit sh;
    if (!intersectSegment(ray, vertex(seg.v0), vertex(seg.v1), g.radii()[seg.v0], g.radii()[seg.v1], sh))
      return false;
    out = segmentHit(ref, sh);
    return true;
  }
  out.geomID = ref.geomID;
  out.primID = ref.primID;
  out.instID = kInvalidId;
  return true;
}

}  // namespace leaf_detail

// Closest-hit test of one primitive. On an accepted hit closer than
// ray.tfar: updates hit, sets ray.tfar and returns true.
inline bool intersectPrimitive(const SceneContext& ctx, PrimRef ref, RayQuery& ray, Hit& hit,
                               TraversalCounters* counters = nullptr) {
  const Geometry& g = ctx.geometry(ref.geomID);
  if ((g.mask() & ray.mask) == 0 || !g.timeRange().contains(ray.time)) return false;
  if (g.type() == GeometryType::Instance) {
    RayQuery local;
    InstanceFrame frame;
    if (!ctx.instanceMotion(ref.geomID).toLocal(g, ray, local, &frame)) return false;
    local.instID = ray.instID;
    Hit h;
    const Structure& child = ctx.child(ref.geomID);
    const bool found = counters ? child.intersectCounted(local, h, *counters) : child.intersect(local, h);
    if (!found) return false;
    h.Ng = frame.normalToWorld(h.Ng);
    h.instID = ref.geomID;
    hit = h;
    ray.tfar = h.t;
    return true;
  }
  Hit h;
  if (!leaf_detail::candidate(g, ref, ray, h) || !leaf_detail::accept(g, ray, h)) return false;
  hit = h;
  ray.tfar = h.t;
  return true;
}

// Any-hit test of one primitive.
inline bool occludedPrimitive(const SceneContext& ctx, PrimRef ref, const RayQuery& ray) {
  const Geometry& g = ctx.geometry(ref.geomID);
  if ((g.mask() & ray.mask) == 0 || !g.timeRange().contains(ray.time)) return false;
  if (g.type() == GeometryType::Instance) {
    RayQuery local;
    if (!ctx.instanceMotion(ref.geomID).toLocal(g, ray, local, nullptr)) return false;
    return ctx.child(ref.geomID).occluded(local);
  }
  Hit h;
  return leaf_detail::candidate(g, ref, ray, h) && leaf_detail::accept(g, ray, h);
}

}  // namespace mbrt::detail
